/**
 * Cross-runtime determinism (issue #2, Tests): the same 1,000 drops, spread
 * over every board (rows 8-16 × low/medium/high), under every shipped engine
 * version, must give bit-identical
 * outcomes (bucket, ticks and the hash of the ball's exact final state) in
 * Node (V8) and in engines that are not V8:
 *   - Bun (JavaScriptCore), running the probe and the engine from source;
 *   - QuickJS (interpreter compiled to WebAssembly, quickjs-emscripten),
 *     running the esbuild bundle of probe + engine + seedrandom.
 * The drop seeds are fixed HMAC-SHA256 hex strings computed here in Node and
 * handed to the other runtimes as data (tests/helpers/determinism-inputs.js).
 * The probe (tests/engine/fixtures/determinism-probe.js) and its bundle
 * (tests/helpers/engine-bundle.js) are meant to be reused as they are by the
 * headless-Chromium run once the client exists.
 *
 * Bun is a devDependency whose binary is fetched by its postinstall script;
 * if it is missing this test fails (it never skips).
 */
import { describe, it, expect, beforeAll } from 'vitest'
import { execFile } from 'node:child_process'
import { existsSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { getQuickJS } from 'quickjs-emscripten'
import { readFileSync } from 'node:fs'
import { ENGINE_VERSIONS } from '../../engine/index.js'
import { determinismDropsOfEveryVersion, ALL_ROWS, ALL_RISKS } from '../helpers/determinism-inputs.js'
import { fixtureFile } from './fixtures/record-determinism-hashes.js'
import { buildProbeBundle, PROBE_GLOBAL } from '../helpers/engine-bundle.js'
import { runDeterminismProbe } from './fixtures/determinism-probe.js'

const DROPS_PER_VERSION = 1000
const DROP_COUNT = DROPS_PER_VERSION * ENGINE_VERSIONS.length
const ROOT = fileURLToPath(new URL('../../', import.meta.url))
const BUN = join(ROOT, 'node_modules', '.bin', 'bun')
const BUN_RUNNER = fileURLToPath(new URL('./fixtures/bun-probe-runner.js', import.meta.url))

/**
 * The first drop whose physics outcome differs, with both sides, or null.
 * Multipliers are not compared: they are a table lookup, not physics.
 */
function firstDifference (expected, actual) {
  if (expected.length !== actual.length) return { reason: `expected ${expected.length} results, got ${actual.length}` }
  let differing = 0
  let first = null
  for (let i = 0; i < expected.length; i++) {
    const a = expected[i]
    const b = actual[i]
    if (a.bucket === b.bucket && a.ticks === b.ticks && a.stateHash === b.stateHash && a.dropSeed === b.dropSeed) continue
    differing++
    first ??= {
      index: i,
      drop: { rows: a.rows, risk: a.risk, dropSeed: a.dropSeed },
      node: { bucket: a.bucket, ticks: a.ticks, stateHash: a.stateHash },
      other: { dropSeed: b.dropSeed, bucket: b.bucket, ticks: b.ticks, stateHash: b.stateHash }
    }
  }
  return first && { ...first, differingDrops: differing }
}

function expectSameOutcomes (node, other, runtime) {
  expect(other.engineVersions, `${runtime} has other engine versions`).toEqual(node.engineVersions)
  expect(other.count).toBe(DROP_COUNT)
  expect(other.digests, `${runtime} digest per engine version`).toEqual(node.digests)
  expect(firstDifference(node.results, other.results), `first drop where ${runtime} disagrees with Node`).toBeNull()
  expect(other.digest, `${runtime} digest over all outcomes`).toBe(node.digest)
}

function runBun (dropsFile) {
  if (!existsSync(BUN)) {
    throw new Error(`Bun binary not found at ${BUN}: run \`npm install\` (the bun devDependency's postinstall fetches it). The cross-runtime test needs it and does not skip.`)
  }
  return new Promise((resolve, reject) => {
    execFile(BUN, ['run', BUN_RUNNER, dropsFile], { cwd: ROOT, maxBuffer: 64 * 1024 * 1024, timeout: 90_000 }, (error, stdout, stderr) => {
      if (error) {
        reject(new Error(`bun failed (${error.code ?? error.signal}): ${error.message}\n${stderr}`))
        return
      }
      try {
        resolve(JSON.parse(stdout))
      } catch (parseError) {
        reject(new Error(`bun printed no JSON: ${parseError.message}\nstdout: ${stdout.slice(0, 2000)}\nstderr: ${stderr}`))
      }
    })
  })
}

describe(`cross-runtime determinism: ${DROPS_PER_VERSION} drops on every board under each of ${ENGINE_VERSIONS.join(', ')}`, () => {
  const drops = determinismDropsOfEveryVersion(DROPS_PER_VERSION)
  let node

  beforeAll(() => {
    const started = performance.now()
    node = runDeterminismProbe(drops)
    console.info(`[cross-runtime] Node ${process.versions.node} (V8 ${process.versions.v8}): ${DROP_COUNT} drops in ${(performance.now() - started).toFixed(0)} ms, digest ${node.digest}`)
  })

  it('covers every rows × risk board and is reproducible within Node', () => {
    const boards = new Set(drops.map((d) => `${d.rows}:${d.risk}`))
    expect(boards.size).toBe(ALL_ROWS.length * ALL_RISKS.length)
    expect(new Set(drops.map((d) => `${d.engineVersion}:${d.dropSeed}`)).size).toBe(DROP_COUNT)
    expect(node.engineVersions).toEqual(ENGINE_VERSIONS)
    expect(node.count).toBe(DROP_COUNT)
    // Each version's digest is the one recorded when it shipped (so every runtime below matches the record too).
    for (const version of ENGINE_VERSIONS) {
      expect(node.digests[version], `engine ${version}`).toBe(JSON.parse(readFileSync(fixtureFile(version), 'utf8')).crossRuntime.digest)
    }
    for (const r of node.results) {
      expect(r.stateHash).toMatch(/^[0-9a-f]{16}$/)
      expect(r.bucket).toBeGreaterThanOrEqual(0)
      expect(r.bucket).toBeLessThanOrEqual(r.rows)
    }
    // A second run in the same process (warm JIT, reused boards) agrees too.
    expect(runDeterminismProbe(drops).digest).toBe(node.digest)
  })

  it('Bun (JavaScriptCore) gives the same outcome for every drop', async () => {
    const dir = mkdtempSync(join(tmpdir(), 'plinko-cross-runtime-'))
    try {
      const dropsFile = join(dir, 'drops.json')
      writeFileSync(dropsFile, JSON.stringify(drops))
      const started = performance.now()
      const bun = await runBun(dropsFile)
      console.info(`[cross-runtime] Bun ${bun.runtime.bun} (JavaScriptCore ${bun.runtime.webkit}): ${DROP_COUNT} drops in ${bun.elapsedMs.toFixed(0)} ms (${(performance.now() - started).toFixed(0)} ms with start-up), digest ${bun.digest}`)
      // Prove this really was Bun on JavaScriptCore, not a Node fallback.
      expect(bun.runtime.bun).toMatch(/^\d+\.\d+/)
      expect(bun.runtime.webkit).toBeTruthy()
      expectSameOutcomes(node, bun, 'Bun (JavaScriptCore)')
    } finally {
      rmSync(dir, { recursive: true, force: true })
    }
  }, 120_000)

  it('QuickJS (WebAssembly interpreter) gives the same outcome for every drop', async () => {
    const source = await buildProbeBundle()
    const quickjs = await getQuickJS()
    const context = quickjs.newContext()
    try {
      const loaded = context.evalCode(source, 'determinism-probe.bundle.js')
      if (loaded.error) throw new Error(`QuickJS could not evaluate the probe bundle: ${JSON.stringify(context.dump(loaded.error))}`)
      loaded.value.dispose()
      const input = context.newString(JSON.stringify(drops))
      context.setProp(context.global, '__probeDrops', input)
      input.dispose()
      const started = performance.now()
      const ran = context.evalCode(`JSON.stringify(globalThis.${PROBE_GLOBAL}.runDeterminismProbe(JSON.parse(globalThis.__probeDrops)))`, 'run-probe.js')
      const elapsedMs = performance.now() - started
      if (ran.error) throw new Error(`QuickJS probe run failed: ${JSON.stringify(context.dump(ran.error))}`)
      const result = JSON.parse(context.getString(ran.value))
      ran.value.dispose()
      console.info(`[cross-runtime] QuickJS (quickjs-emscripten, WebAssembly): ${DROP_COUNT} drops in ${elapsedMs.toFixed(0)} ms, digest ${result.digest}`)
      expectSameOutcomes(node, result, 'QuickJS')
    } finally {
      context.dispose()
    }
  }, 180_000)
})
