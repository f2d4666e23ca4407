/**
 * The engine as a standard (docs/engine-spec.md): the second implementation,
 * verifier-python/ (Python, standard library only, following the spec),
 * must give every drop of every shipped version the same bucket, ticks and
 * state hash as the JavaScript engine.
 *
 * These tests are part of `npm test`, not of a Python test runner of their
 * own: the Python implementation is only worth something while it stays equal
 * to the engine, so it is checked on every run of the suite CI already runs
 * (.ci/run), with nothing more to install than python3 (3.8 or newer, with
 * its venv module). They run python3 as a child process, as an auditor would.
 *
 * Each run draws fresh random seeds: the run's key is printed; set
 * PLINKO_SPEC_SEED=<key> to replay exactly the same drops.
 */
import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { execFile } from 'node:child_process'
import { createHmac, randomBytes } from 'node:crypto'
import { mkdtempSync, readdirSync, readFileSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { createBoard, simulateDrop, ENGINE_VERSIONS, RISKS, MIN_ROWS, MAX_ROWS } from '../../engine/index.js'
import { vectorsText, VECTORS_FILE } from '../../scripts/engine-spec-vectors.js'
import { verifyCommand } from '../../cli/verify-command.js'
import { traceDrop } from '../../scripts/trace-drop.js'

const ROOT = fileURLToPath(new URL('../../', import.meta.url))
const VERIFIER = join(ROOT, 'verifier-python')
const FIXTURES = join(ROOT, 'tests/engine/fixtures')
const PLINKO = join(ROOT, 'bin/plinko.js')
/** Random drops per board and version: 27 boards × 2 versions × 20 = 1,080 a run (a few seconds). */
const DROPS_PER_BOARD = 20

/** Runs `command args` with `input` on stdin; resolves { code, stdout, stderr }. */
function run (command, args, { input, env } = {}) {
  return new Promise((resolve) => {
    const child = execFile(command, args, { timeout: 120_000, maxBuffer: 64 << 20, env: { ...process.env, ...env } }, (error, stdout, stderr) => {
      resolve({ code: error ? (error.code ?? 1) : 0, stdout, stderr })
    })
    child.stdin.end(input ?? '')
  })
}

/**
 * `plinko verify args` run in this process (bin/plinko.js prints what
 * verifyCommand writes, and `plinko verify: <message>` for what it throws):
 * { code, stdout, stderr } as the command would answer.
 */
async function plinkoVerifyInProcess (args) {
  let stdout = ''
  try {
    await verifyCommand(args, { write: (text) => { stdout += text } })
    return { code: 0, stdout, stderr: '' }
  } catch (error) {
    return { code: 2, stdout, stderr: `plinko verify: ${error.message}\n` }
  }
}

/** The package run from its folder, as `python3 -m plinko_verify ...` (no bytecode written into the tree). */
function plinkoVerify (args, input) {
  return run('python3', ['-m', 'plinko_verify', ...args], { input, env: { PYTHONPATH: VERIFIER, PYTHONDONTWRITEBYTECODE: '1' } })
}

/** Outcomes of `drops` ({ engineVersion, rows, risk, dropSeed }) from the Python implementation, in order. */
async function pythonOutcomes (drops) {
  const { code, stdout, stderr } = await plinkoVerify(['replay'], drops.map((drop) => JSON.stringify(drop)).join('\n') + '\n')
  expect(stderr).toBe('')
  expect(code).toBe(0)
  return stdout.trim().split('\n').map((line) => JSON.parse(line))
}

/** The drops whose Python outcome differs from the engine's, with both outcomes. */
async function mismatches (drops) {
  const python = await pythonOutcomes(drops)
  expect(python).toHaveLength(drops.length)
  const different = []
  drops.forEach((drop, i) => {
    const { bucket, multiplier, ticks, stateHash } = simulateDrop(createBoard(drop), drop.dropSeed)
    const javascript = { bucket, multiplier, ticks, stateHash }
    if (JSON.stringify(javascript) !== JSON.stringify(python[i])) different.push({ drop, javascript, python: python[i] })
  })
  return different
}

describe('verifier-python reproduces the engine', () => {
  it('every fixture drop of every shipped version', async () => {
    const files = readdirSync(FIXTURES).filter((name) => /^engine-.*\.json$/.test(name))
    expect(files.map((name) => name.slice('engine-'.length, -'.json'.length)).sort()).toEqual([...ENGINE_VERSIONS].sort())
    const drops = []
    const recorded = []
    for (const file of files) {
      const fixture = JSON.parse(readFileSync(join(FIXTURES, file), 'utf8'))
      for (const { rows, risk, dropSeed, bucket, ticks, stateHash } of fixture.drops) {
        drops.push({ engineVersion: fixture.engineVersion, rows, risk, dropSeed })
        recorded.push({ bucket, ticks, stateHash })
      }
    }
    const python = await pythonOutcomes(drops)
    expect(python.map(({ bucket, ticks, stateHash }) => ({ bucket, ticks, stateHash }))).toEqual(recorded)
    expect(python.map(({ multiplier }) => multiplier)).toEqual(drops.map((drop, i) => createBoard(drop).multipliers[recorded[i].bucket]))
  })

  it(`fresh random seeds on all 27 boards of every version (${DROPS_PER_BOARD} drops each)`, async () => {
    const key = process.env.PLINKO_SPEC_SEED || randomBytes(16).toString('hex')
    console.log(`python-verifier random drops: PLINKO_SPEC_SEED=${key} replays this run's drops`)
    const drops = []
    for (const engineVersion of ENGINE_VERSIONS) {
      for (const risk of RISKS) {
        for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
          for (let i = 0; i < DROPS_PER_BOARD; i++) {
            const dropSeed = createHmac('sha256', key).update(`${engineVersion}:${rows}:${risk}:${i}`).digest('hex')
            drops.push({ engineVersion, rows, risk, dropSeed })
          }
        }
      }
    }
    expect(drops.length).toBeGreaterThanOrEqual(500)
    expect(await mismatches(drops), `PLINKO_SPEC_SEED=${key}`).toEqual([])
  })

  it('every multiplier table of every version, to the bit', async () => {
    const script = 'from plinko_verify.multipliers import MULTIPLIERS\nfrom plinko_verify.js_json import stringify\n' +
      'print(stringify({v: {str(rows): {risk: list(t) for risk, t in risks.items()} for rows, risks in tables.items()} for v, tables in MULTIPLIERS.items()}))'
    const { code, stdout } = await run('python3', ['-c', script], { env: { PYTHONPATH: VERIFIER, PYTHONDONTWRITEBYTECODE: '1' } })
    expect(code).toBe(0)
    const engine = Object.fromEntries(ENGINE_VERSIONS.map((version) => [version, Object.fromEntries(
      Array.from({ length: MAX_ROWS - MIN_ROWS + 1 }, (_, i) => MIN_ROWS + i).map((rows) => [rows, Object.fromEntries(RISKS.map((risk) => [risk, createBoard({ rows, risk, engineVersion: version }).multipliers]))])
    )]))
    // Shortest round-trip decimals: equal text is equal doubles.
    expect(stdout).toBe(JSON.stringify(engine) + '\n')
  })

  it('the tick cap: a ball still in play after maxDropTicks lands where it is (no shipped drop reaches 3,600)', async () => {
    const drops = []
    for (const engineVersion of ENGINE_VERSIONS) {
      for (const maxDropTicks of [1, 12, 100]) {
        for (const rows of [8, 16]) {
          const dropSeed = createHmac('sha256', 'tick-cap').update(`${engineVersion}:${rows}:${maxDropTicks}`).digest('hex')
          drops.push({ engineVersion, rows, risk: 'high', dropSeed, maxDropTicks })
        }
      }
    }
    const python = await pythonOutcomes(drops)
    const javascript = drops.map((drop) => {
      const board = createBoard(drop)
      const { bucket, multiplier, ticks, stateHash } = simulateDrop({ ...board, maxDropTicks: drop.maxDropTicks }, drop.dropSeed)
      return { bucket, multiplier, ticks, stateHash }
    })
    expect(python.map(({ ticks }) => ticks)).toEqual(drops.map(({ maxDropTicks }) => maxDropTicks))
    expect(python).toEqual(javascript)
  })
})

describe('the spec\'s test vectors (docs/engine-spec-vectors.json)', () => {
  it('are what the JavaScript engine gives today (node scripts/engine-spec-vectors.js writes them)', async () => {
    expect(await vectorsText()).toBe(readFileSync(VECTORS_FILE, 'utf8'))
  })

  it('are all reproduced by verifier-python', async () => {
    const vectors = JSON.parse(readFileSync(VECTORS_FILE, 'utf8'))
    const versions = Object.values(vectors.versions)
    const count = vectors.seeds.length + vectors.random.length + vectors.stateHash.length +
      versions.reduce((sum, version) => sum + version.boards.length + version.drops.length, 0)
    expect(Object.keys(vectors.versions)).toEqual(ENGINE_VERSIONS)
    const { code, stdout } = await plinkoVerify(['vectors', VECTORS_FILE])
    expect(stdout.split('\n').filter((line) => line.startsWith('FAIL'))).toEqual([])
    expect(stdout).toContain(`\n${count} vectors, 0 failed\n`)
    expect(code).toBe(0)
  })
})

describe('plinko-verify trace', () => {
  it('prints, tick by tick, the lines scripts/trace-drop.js prints from the engine', async () => {
    for (const engineVersion of ENGINE_VERSIONS) {
      const dropSeed = createHmac('sha256', 'trace').update(engineVersion).digest('hex')
      const board = { rows: 12, risk: 'low', engineVersion }
      const { code, stdout } = await plinkoVerify(['trace', '--drop-seed', dropSeed, '--rows', '12', '--risk', 'low', '--engine-version', engineVersion])
      expect(code).toBe(0)
      const javascript = [...traceDrop(createBoard(board), dropSeed)].map((line) => JSON.stringify(line) + '\n').join('')
      expect(stdout.split('\n').length).toBeGreaterThan(50)
      expect(stdout).toBe(javascript)
    }
  })
})

/** Argument lists `plinko verify` and `plinko-verify verify` must answer alike. */
const VERIFY_CASES = [
  ['--server-seed', 'f6d91647a622851ecffa08a3b705ea6dfde317b186c919ac981783fc0a5833b5', '--client-seed', 'lucky-7', '--nonce', '7', '--rows', '16', '--risk', 'high', '--engine-version', '1.0.0'],
  ['--server-seed', 'revealed', '--client-seed', 'mine', '--nonce', '12', '--rows', '9', '--risk', 'low'],
  ['--server-seed=ünï€ 😀', '--client-seed=', '--nonce=9007199254740991', '--rows=12', '--engine-version=2.0.0'],
  ['--server-seed', '-x', '--client-seed', '-y', '--nonce', '007', '--risk', 'medium', '--engine-version', '1.0.0', '--rows', '8']
]
/** Bad command lines: the same message (the program's name aside) and exit code 2. */
const BAD_VERIFY_CASES = [
  ['--server-seed', 'a', '--client-seed', '--nonce', '1'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '-1'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '9007199254740992'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '1', '--bogus'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '1', 'extra'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '1', '--rows', '8', '--rows', '9'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '1', '--rows', '17'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '1', '--risk', 'big'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '1', '--engine-version', '3.0.0'],
  ['--server-seed', '', '--client-seed', 'x', '--nonce', '1'],
  ['--server-seed', 'a', '--nonce', '1'],
  ['--server-seed', 'a', '--client-seed', 'x'],
  ['--server-seed', 'a', '--client-seed', 'x', '--nonce', '1', '--help=yes']
]

describe('plinko-verify verify is plinko verify', () => {
  it.each(VERIFY_CASES)('the same JSON, byte for byte: %j', async (...args) => {
    const [node, python] = await Promise.all([plinkoVerifyInProcess(args), plinkoVerify(['verify', ...args])])
    expect(node.code).toBe(0)
    expect(python.stderr).toBe('')
    expect(python.stdout).toBe(node.stdout)
    expect(python.code).toBe(0)
  })

  it('answers a bad command line as plinko verify does: the same reason, exit code 2', async () => {
    const answers = await Promise.all(BAD_VERIFY_CASES.map((args) => Promise.all([plinkoVerifyInProcess(args), plinkoVerify(['verify', ...args])])))
    BAD_VERIFY_CASES.forEach((args, i) => {
      const [node, python] = answers[i]
      expect(node.code, args.join(' ')).toBe(2)
      expect(python.code, args.join(' ')).toBe(2)
      expect(python.stdout).toBe('')
      expect(python.stderr.split('\n')[0].replace('plinko-verify verify:', 'plinko verify:'), args.join(' ')).toBe(node.stderr.split('\n')[0])
    })
  })
})

describe('pip install ./verifier-python', () => {
  let dir
  beforeAll(() => { dir = mkdtempSync(join(tmpdir(), 'plinko-verify-venv-')) })
  afterAll(() => { if (dir) rmSync(dir, { recursive: true, force: true }) })

  it('installs into a fresh virtual environment without a package index, and its plinko-verify prints what plinko verify prints', async () => {
    const venv = join(dir, 'venv')
    const created = await run('python3', ['-m', 'venv', venv])
    expect(created.stderr).toBe('')
    expect(created.code).toBe(0)
    // --no-index: the in-tree build backend needs nothing downloaded.
    const installed = await run(join(venv, 'bin', 'pip'), ['install', '--no-index', '--no-cache-dir', '--disable-pip-version-check', '--quiet', VERIFIER])
    expect(installed.stderr).toBe('')
    expect(installed.code).toBe(0)
    for (const args of [VERIFY_CASES[0], VERIFY_CASES[2]]) {
      const [node, installedRun] = await Promise.all([run(process.execPath, [PLINKO, 'verify', ...args]), run(join(venv, 'bin', 'plinko-verify'), ['verify', ...args])])
      expect(node.code).toBe(0)
      expect(installedRun.stdout).toBe(node.stdout)
      expect(installedRun.code).toBe(0)
    }
    // The installed copy is the package (not the checkout): it runs from the venv.
    const where = await run(join(venv, 'bin', 'python'), ['-c', 'import plinko_verify; print(plinko_verify.__file__)'])
    expect(where.stdout.startsWith(venv)).toBe(true)
  }, 180_000) // a venv and a pip run: about 10 s on a quiet machine, several times that on a busy one
})
