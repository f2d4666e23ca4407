import path from 'node:path'
import { build } from 'esbuild'

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
 * @param {object} sources what client-assets.js serves: the same files go in the bundle
 * @param {Record<string, string>} sources.sharedDirs URL prefix → folder (`/engine/…` → engine/)
 * @param {string} sources.seedrandom the file /vendor/seedrandom.js wraps (seedrandom's ARC4 generator, the function the engine calls)
 * @returns {Promise<string>}
 */
export async function buildPageBundle (entry, { sharedDirs, seedrandom }) {
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
    plugins: [sharedFilesPlugin(sharedDirs, seedrandom)]
  })
  return result.outputFiles[0].text
}

/** Resolves `/engine/…`, `/protocol/…`, `/charts/…` and `seedrandom` to the files the server serves for them. */
function sharedFilesPlugin (sharedDirs, seedrandom) {
  const filter = new RegExp(`^/(${Object.keys(sharedDirs).join('|')})/(.*)$`)
  return {
    name: 'plinko-shared-dirs',
    setup (build) {
      build.onResolve({ filter }, (args) => {
        const [, prefix, file] = filter.exec(args.path)
        return { path: path.join(sharedDirs[prefix], file) }
      })
      build.onResolve({ filter: /^seedrandom$/ }, () => ({ path: seedrandom }))
    }
  }
}
