import { describe, it, expect } from 'vitest'
import { execFile } from 'node:child_process'
import { createHash, createHmac } from 'node:crypto'
import { mkdtempSync, readFileSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { createBoard, simulateDrop, ENGINE_VERSION } from '../../engine/index.js'

const PLINKO = fileURLToPath(new URL('../../bin/plinko.js', import.meta.url))

function plinko (...args) {
  return new Promise((resolve) => {
    execFile(process.execPath, [PLINKO, ...args], { timeout: 120_000 }, (error, stdout, stderr) => {
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

      const text = await plinko('rtp', '--rows', '8', '--drops', '500', '--chart', join(dir, 'b.svg'))
      expect(text.code).toBe(0)
      expect(text.stdout).toMatch(/RTP \d+\.\d+% \(95% CI/)
      expect(text.stderr).toMatch(/100%/) // progress reached the end
    } finally {
      rmSync(dir, { recursive: true, force: true })
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
      ['rtp', '--drops', '0'],
      ['rtp', '--unknown']
    ]) {
      const { code, stderr } = await plinko(...args)
      expect(code, args.join(' ')).toBe(2)
      expect(stderr).toMatch(/usage:/)
    }
  })
})
