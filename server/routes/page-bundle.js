import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { createRequire } from 'node:module'
import { build } from 'esbuild'

/** The folders the pages import by absolute URL, served as they are at /NAME/ (client-assets.js). */
const SHARED_DIRS = ['engine', 'protocol', 'charts']
const ROOT = fileURLToPath(new URL('../../', import.meta.url))
/** The same file /vendor/seedrandom.js wraps: seedrandom's ARC4 generator, the function the engine calls. */
const SEEDRANDOM = createRequire(import.meta.url).resolve('seedrandom/seedrandom.js')

/**
 * The player page's whole module graph as one ES module, built once at
 * start by esbuild from the very files the server runs and serves (the
 * engine, the wire format, seedrandom, the page's own modules), not
 * minified and not transpiled. Why: over HTTP/1.1 a browser fetches at most
 * six files at a time, so the page's ~55 modules took ten round trips; on a
 * 300 ms link that alone was 3 s before the board could be drawn. The
 * plain modules stay served at their URLs (the operator page, and anyone
 * checking the engine, read them there); tests/e2e/chromium-determinism
 * holds the bundled engine to Node's outcome bit for bit.
 * @param {string} entry the page's entry module (client/player.js)
 * @returns {Promise<string>}
 */
export async function buildPageBundle (entry) {
  const result = await build({
    entryPoints: [entry],
    bundle: true,
    format: 'esm',
    // Honours seedrandom's "browser" field: its optional require('crypto') becomes empty.
    platform: 'browser',
    target: 'esnext',
    minify: false,
    write: false,
    charset: 'utf8',
    legalComments: 'inline',
    logLevel: 'silent',
    plugins: [sharedDirsPlugin()]
  })
  return result.outputFiles[0].text
}

/** Resolves `/engine/…`, `/protocol/…` and `/charts/…` to the repository's folders, as the server serves them. */
function sharedDirsPlugin () {
  const filter = new RegExp(`^/(${SHARED_DIRS.join('|')})/`)
  return {
    name: 'plinko-shared-dirs',
    setup (build) {
      build.onResolve({ filter }, (args) => ({ path: path.join(ROOT, args.path) }))
      build.onResolve({ filter: /^seedrandom$/ }, () => ({ path: SEEDRANDOM }))
    }
  }
}
