/**
 * Cross-runtime determinism in headless Chromium (issue #2, Tests): the
 * same 1,000 drops over every board as tests/engine/cross-runtime.test.js
 * must give bit-identical outcomes (bucket, ticks, hash of the ball's
 * exact final state) in Chromium's V8 and in Node. Two ways in:
 *   - the way the game loads it: the repository's engine/ files as ES
 *     modules from the real server at /engine/, with 'seedrandom' mapped by
 *     the page's import map to /vendor/seedrandom.js, under the page's CSP;
 *   - the esbuild bundle of probe + engine + seedrandom
 *     (tests/helpers/engine-bundle.js), as QuickJS runs it.
 */
import { describe, it, expect } from 'vitest'
import { readFileSync } from 'node:fs'
import { fileURLToPath } from 'node:url'
import { serverAndChromium } from './helpers/testbed.js'
import { ENGINE_VERSIONS } from '../../engine/index.js'
import { determinismDropsOfEveryVersion } from '../helpers/determinism-inputs.js'
import { buildProbeBundle, PROBE_GLOBAL } from '../helpers/engine-bundle.js'
import { runDeterminismProbe } from '../engine/fixtures/determinism-probe.js'

const DROP_COUNT = 1000 * ENGINE_VERSIONS.length
const PROBE_FILE = fileURLToPath(new URL('../engine/fixtures/determinism-probe.js', import.meta.url))

let server
let chromium
let node
const drops = determinismDropsOfEveryVersion(1000)

serverAndChromium({}, async (started) => {
  ({ server, chromium } = started)
  node = runDeterminismProbe(drops)
})

function expectSameOutcomes (chrome, how) {
  expect(chrome.engineVersions).toEqual(node.engineVersions)
  expect(chrome.count).toBe(DROP_COUNT)
  expect(chrome.digests).toEqual(node.digests)
  let first = null
  let differing = 0
  for (let i = 0; i < DROP_COUNT; i++) {
    const a = node.results[i]
    const b = chrome.results[i]
    if (a.dropSeed === b.dropSeed && a.bucket === b.bucket && a.ticks === b.ticks && a.stateHash === b.stateHash) continue
    differing++
    first ??= { index: i, node: a, chromium: b }
  }
  expect(first && { ...first, differing }, `first drop where Chromium (${how}) disagrees with Node`).toBeNull()
  expect(chrome.digest).toBe(node.digest)
}

describe(`Chromium determinism: 1,000 drops on every board under each of ${ENGINE_VERSIONS.join(', ')}`, () => {
  it('the engine served at /engine/ through the import map gives Node\'s outcome for every drop', async () => {
    const page = await chromium.newPage()
    // The probe module, served from the repository at its own path; its
    // imports (../../../engine/*.js) resolve to the server's /engine/.
    await page.route('**/tests/engine/fixtures/determinism-probe.js', (route) => route.fulfill({
      status: 200,
      contentType: 'text/javascript; charset=utf-8',
      body: readFileSync(PROBE_FILE, 'utf8')
    }))
    // The operator page: it has the import map and the real CSP, and does nothing until signed in.
    await page.goto(`${server.base}/audit`)
    await page.evaluate((drops) => { window.__probeDrops = drops }, drops)
    // A string, not a function: vitest would rewrite a function's import() for Node.
    const result = await page.evaluate(`(async () => {
      const started = performance.now()
      const { runDeterminismProbe } = await import('/tests/engine/fixtures/determinism-probe.js')
      const probe = runDeterminismProbe(window.__probeDrops)
      const seedrandom = (await import('seedrandom')).default
      return { ...probe, elapsedMs: performance.now() - started, userAgent: navigator.userAgent, seedrandomSample: seedrandom('abc')() }
    })()`)
    console.info(`[chromium-determinism] ${result.userAgent}: ${DROP_COUNT} drops via /engine/ in ${result.elapsedMs.toFixed(0)} ms, digest ${result.digest} (Node ${node.digest})`)
    expect(result.userAgent).toContain('HeadlessChrome')
    // seedrandom in the browser is the very generator Node uses.
    const { default: seedrandom } = await import('seedrandom')
    expect(result.seedrandomSample).toBe(seedrandom('abc')())
    expectSameOutcomes(result, '/engine/ modules')
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('the esbuild bundle gives Node\'s outcome for every drop', async () => {
    const page = await chromium.newPage()
    await page.setContent('<!doctype html><title>probe</title>')
    await page.addScriptTag({ content: await buildProbeBundle() })
    const result = await page.evaluate(([name, drops]) => {
      const started = performance.now()
      const probe = globalThis[name].runDeterminismProbe(drops)
      return { ...probe, elapsedMs: performance.now() - started }
    }, [PROBE_GLOBAL, drops])
    console.info(`[chromium-determinism] bundle: ${DROP_COUNT} drops in ${result.elapsedMs.toFixed(0)} ms, digest ${result.digest}`)
    expectSameOutcomes(result, 'bundle')
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
