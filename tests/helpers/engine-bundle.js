import { fileURLToPath } from 'node:url'
import { build } from 'esbuild'

/** Path of the runtime-neutral probe module (imports engine code only). */
export const PROBE_ENTRY = fileURLToPath(new URL('../engine/fixtures/determinism-probe.js', import.meta.url))

/**
 * Name of the global the bundle defines. After evaluating the bundle as a
 * classic script, `globalThis[PROBE_GLOBAL].runDeterminismProbe(drops)`
 * returns { engineVersion, count, digest, results }.
 */
export const PROBE_GLOBAL = 'PlinkoDeterminismProbe'

let cached = null

/**
 * Bundles the probe, the engine and seedrandom into one self-contained
 * classic script (IIFE, ES2020) that needs no module loader and no host API,
 * for engines that cannot load our ESM files themselves: QuickJS here, and
 * headless Chromium later (inject it with page.addScriptTag({ content }) and
 * call it through page.evaluate).
 *
 * platform 'browser' makes esbuild honour seedrandom's "browser" field
 * ({ crypto: false }), so its optional require('crypto') becomes an empty
 * module instead of a Node built-in; seedrandom only uses it to autoseed,
 * which the engine never does (it always passes the drop seed).
 *
 * @returns {Promise<string>} the bundled source (cached per process)
 */
export async function buildProbeBundle () {
  if (cached) return cached
  const result = await build({
    entryPoints: [PROBE_ENTRY],
    bundle: true,
    format: 'iife',
    globalName: PROBE_GLOBAL,
    platform: 'browser',
    target: 'es2020',
    minify: false,
    write: false,
    logLevel: 'silent'
  })
  const source = result.outputFiles[0].text
  // The IIFE's top-level `var` is a global in a classic script; assign it
  // explicitly too so the bundle also works when evaluated in a function scope.
  cached = `${source}\nglobalThis.${PROBE_GLOBAL} = ${PROBE_GLOBAL};\n`
  return cached
}
