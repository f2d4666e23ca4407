import { describe, it, expect } from 'vitest'
import { execFile } from 'node:child_process'
import { createHash, createHmac } from 'node:crypto'
import { mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { createBoard, simulateDrop, ENGINE_VERSION, ENGINE_VERSIONS } from '../../engine/index.js'
import { ledgerFixture, fixtureDrops } from '../helpers/ledger-fixture.js'

const PLINKO = fileURLToPath(new URL('../../bin/plinko.js', import.meta.url))

function plinko (...args) {
  return plinkoIn(undefined, ...args)
}

function plinkoIn (cwd, ...args) {
  return new Promise((resolve) => {
    execFile(process.execPath, [PLINKO, ...args], { timeout: 120_000, cwd }, (error, stdout, stderr) => {
      resolve({ code: error ? error.code : 0, stdout, stderr })
    })
  })
}

describe('plinko CLI', () => {
  it('verify prints the whole chain as one JSON object', async () => {
    const { code, stdout } = await plinko('verify', '--server-seed', 'revealed', '--client-seed', 'mine', '--nonce', '12', '--rows', '9', '--risk', 'low')
    expect(code).toBe(0)
    const result = JSON.parse(stdout)
    const dropSeed = createHmac('sha256', 'revealed').update('mine:12').digest('hex')
    expect(result).toEqual({
      serverSeedHash: createHash('sha256').update('revealed').digest('hex'),
      dropSeed,
      ...simulateDrop(createBoard({ rows: 9, risk: 'low' }), dropSeed),
      engineVersion: ENGINE_VERSION
    })
  })

  it('rtp simulates, prints the distribution and the RTP with its interval, and writes a chart', async () => {
    const dir = mkdtempSync(join(tmpdir(), 'plinko-rtp-'))
    try {
      const chart = join(dir, 'chart.svg')
      const { code, stdout } = await plinko('rtp', '--rows', '8', '--risk', 'high', '--drops', '2000', '--server-seed', 's', '--workers', '2', '--chart', chart, '--json')
      expect(code).toBe(0)
      const summary = JSON.parse(stdout)
      expect(summary.counts.reduce((a, b) => a + b, 0)).toBe(2000)
      // The same drops simulated here give the same counts.
      const board = createBoard({ rows: 8, risk: 'high' })
      const counts = new Array(9).fill(0)
      for (let n = 0; n < 2000; n++) counts[simulateDrop(board, createHmac('sha256', 's').update(`rtp:${n}`).digest('hex')).bucket]++
      expect(summary.counts).toEqual(counts)
      const rtp = counts.reduce((sum, c, i) => sum + c * board.multipliers[i], 0) / 2000
      expect(summary.rtp).toBeCloseTo(rtp, 12)
      expect(summary.ci95[0]).toBeLessThan(rtp)
      expect(summary.ci95[1]).toBeGreaterThan(rtp)
      const svg = readFileSync(chart, 'utf8')
      expect(svg).toMatch(/^<svg/)
      expect(svg.match(/<rect /g).length).toBeGreaterThanOrEqual(10)

      expect(summary.chart).toBe(chart)

      // A relative --chart is written there and reported as an absolute path.
      mkdirSync(join(dir, 'out'))
      const text = await plinkoIn(dir, 'rtp', '--rows', '8', '--drops', '500', '--chart', join('out', 'b.svg'))
      expect(text.code).toBe(0)
      expect(text.stdout).toMatch(/RTP \d+\.\d+% \(95% CI/)
      expect(text.stdout).toContain(`chart written to ${join(dir, 'out', 'b.svg')}\n`)
      expect(readFileSync(join(dir, 'out', 'b.svg'), 'utf8')).toMatch(/^<svg/)
      expect(text.stderr).toMatch(/100%/) // progress reached the end
    } finally {
      rmSync(dir, { recursive: true, force: true })
    }
  })

  it('verify --engine-version reproduces drops a 1.0.0 server recorded before the upgrade', async () => {
    const fixture = ledgerFixture('1.0.0')
    const a = fixture.players.a
    const revealed = fixtureDrops(fixture).filter((d) => d.server_seed_hash === a.revealedServerSeedHash && d.status === 'settled')
    expect(revealed.length).toBeGreaterThan(10)
    for (const drop of revealed.slice(0, 4)) {
      const args = ['verify', '--server-seed', a.revealedServerSeed, '--client-seed', drop.client_seed, '--nonce', String(drop.nonce), '--rows', String(drop.rows), '--risk', drop.risk]
      const old = await plinko(...args, '--engine-version', '1.0.0')
      expect(old.code).toBe(0)
      expect(JSON.parse(old.stdout)).toEqual({
        serverSeedHash: a.revealedServerSeedHash,
        dropSeed: drop.drop_seed,
        bucket: drop.bucket,
        multiplier: drop.multiplier,
        ticks: drop.ticks,
        stateHash: drop.state_hash,
        engineVersion: '1.0.0'
      })
      // Without --engine-version: the newest engine, another outcome.
      const newest = JSON.parse((await plinko(...args)).stdout)
      expect(newest.engineVersion).toBe(ENGINE_VERSION)
      expect(newest.stateHash).not.toBe(drop.state_hash)
    }
  })

  it('rtp --engine-version simulates under that version', async () => {
    const dir = mkdtempSync(join(tmpdir(), 'plinko-rtp-'))
    try {
      for (const version of ENGINE_VERSIONS) {
        const { code, stdout } = await plinko('rtp', '--rows', '9', '--risk', 'low', '--drops', '300', '--server-seed', 's', '--workers', '1', '--engine-version', version, '--chart', join(dir, `${version}.svg`), '--json')
        expect(code).toBe(0)
        const summary = JSON.parse(stdout)
        expect(summary.engineVersion).toBe(version)
        const board = createBoard({ rows: 9, risk: 'low', engineVersion: version })
        const counts = new Array(10).fill(0)
        for (let n = 0; n < 300; n++) counts[simulateDrop(board, createHmac('sha256', 's').update(`rtp:${n}`).digest('hex')).bucket]++
        expect(summary.counts).toEqual(counts)
        expect(summary.multipliers).toEqual(board.multipliers)
      }
    } finally {
      rmSync(dir, { recursive: true, force: true })
    }
  })

  it('rtp writes no chart unless --chart says where, and says so', async () => {
    const dir = mkdtempSync(join(tmpdir(), 'plinko-rtp-'))
    try {
      const text = await plinkoIn(dir, 'rtp', '--rows', '8', '--drops', '200', '--workers', '1')
      expect(text.code).toBe(0)
      expect(text.stdout).toContain('no chart written (--chart FILE.svg draws one)')
      const json = await plinkoIn(dir, 'rtp', '--rows', '8', '--drops', '200', '--workers', '1', '--json')
      expect(JSON.parse(json.stdout).chart).toBe(null)
      expect(readdirSync(dir)).toEqual([])
      // A --chart whose folder is missing, or that is a folder, fails before simulating.
      for (const [chart, reason] of [[join(dir, 'missing', 'c.svg'), /the folder .*missing does not exist/], [dir, /is a folder: give a file name/]]) {
        const bad = await plinkoIn(dir, 'rtp', '--drops', '1000000000', '--chart', chart)
        expect(bad.code).toBe(2)
        expect(bad.stderr).toMatch(reason)
        expect(bad.stderr).not.toMatch(/simulating/)
      }
      expect(readdirSync(dir)).toEqual([])
    } finally {
      rmSync(dir, { recursive: true, force: true })
    }
  })

  it('prints each command\'s own usage and options for --help, -h and `plinko help COMMAND`, exit 0', async () => {
    for (const [command, options] of [['verify', ['--server-seed', '--client-seed', '--nonce', '--rows', '--risk', '--engine-version']], ['rtp', ['--drops', '--workers', '--chart', '--json', '--engine-version']], ['bench', ['--quick']]]) {
      const outputs = []
      for (const args of [[command, '--help'], [command, '-h'], ['help', command], [command, '--rows', '99', '--help']]) {
        const { code, stdout, stderr } = await plinko(...args)
        expect(code, args.join(' ')).toBe(0)
        expect(stderr).toBe('')
        outputs.push(stdout)
      }
      expect(new Set(outputs).size).toBe(1)
      expect(outputs[0]).toMatch(new RegExp(`^usage: plinko ${command} `))
      for (const option of options) expect(outputs[0]).toContain(`  ${option} `)
      for (const other of ['verify', 'rtp', 'bench'].filter((c) => c !== command)) expect(outputs[0]).not.toContain(`plinko ${other}`)
    }
    const all = await plinko('--help')
    expect(all.code).toBe(0)
    expect(all.stdout).toMatch(/plinko verify[\s\S]*plinko rtp[\s\S]*plinko bench/)
  })

  it('names the problem in its own words: a negative nonce, a missing value, a repeated option', async () => {
    const seeds = ['--server-seed', 's', '--client-seed', 'c']
    for (const [args, message] of [
      [['verify', ...seeds, '--nonce', '-1'], 'plinko verify: --nonce must be a whole number from 0 to 9007199254740991, got "-1"'],
      [['verify', ...seeds, '--nonce=-1'], 'plinko verify: --nonce must be a whole number from 0 to 9007199254740991, got "-1"'],
      [['verify', '--server-seed', '--client-seed', 'c', '--nonce', '1'], 'plinko verify: --server-seed needs a value'],
      [['verify', ...seeds, '--nonce'], 'plinko verify: --nonce needs a value'],
      [['verify', ...seeds, '--nonce', '1', '--nonce', '2'], 'plinko verify: --nonce given twice: give it once'],
      [['rtp', '--json', '--json'], 'plinko rtp: --json given twice: give it once'],
      [['rtp', '--rows', '8', 'extra'], 'plinko rtp: unexpected argument "extra"']
    ]) {
      const { code, stderr } = await plinko(...args)
      expect(code, args.join(' ')).toBe(2)
      expect(stderr.split('\n')[0]).toBe(message)
      expect(stderr).not.toMatch(/ambiguous/)
      expect(stderr).toContain(`usage: plinko ${args[0]} `)
    }
  })

  it('rejects bad arguments with a clear message and exit code 2', async () => {
    for (const args of [
      [],
      ['frobnicate'],
      ['verify', '--client-seed', 'c', '--nonce', '1'],
      ['verify', '--server-seed', 's', '--client-seed', 'c', '--nonce', '-1'],
      ['verify', '--server-seed', 's', '--client-seed', 'c', '--nonce', '1', '--rows', '20'],
      ['verify', '--server-seed', 's', '--client-seed', 'c', '--nonce', '1', '--risk', 'wild'],
      ['verify', '--server-seed', 's', '--client-seed', 'c', '--nonce', '1', '--engine-version', '0.9.0'],
      ['rtp', '--drops', '10', '--engine-version', 'latest'],
      ['rtp', '--drops', '0'],
      ['rtp', '--unknown'],
      ['help', 'frobnicate']
    ]) {
      const { code, stderr } = await plinko(...args)
      expect(code, args.join(' ')).toBe(2)
      expect(stderr).toMatch(/usage:/)
    }
  })

  it('bench measures the engine alone (no development dependency): a row per version, row count and seed mode', async () => {
    const { code, stdout } = await plinko('bench', '--quick')
    expect(code).toBe(0)
    const rows = stdout.split('\n').filter((line) => /^\s+(16|8)\s/.test(line))
    expect(rows).toHaveLength(2 * ENGINE_VERSIONS.length * 2)
    for (const version of ENGINE_VERSIONS) {
      for (const count of ['16', '8']) {
        const mine = rows.filter((line) => line.trim().startsWith(count + ' ') && line.includes(` ${version} `))
        expect(mine.map((line) => /precomputed|HMAC included/.exec(line)[0]).sort(), `${count} rows, ${version}`).toEqual(['HMAC included', 'precomputed'])
        for (const line of mine) expect(Number(line.trim().split(/\s{2,}/)[3].replace(/,/g, ''))).toBeGreaterThan(0)
      }
    }
    expect(stdout).toMatch(/≥30,000 drops\/s: (met|not met)/)
  })
})
