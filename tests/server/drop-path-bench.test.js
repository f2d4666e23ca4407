import { describe, it, expect } from 'vitest'
import { execFile } from 'node:child_process'
import { fileURLToPath } from 'node:url'

const BENCH = fileURLToPath(new URL('../../bench/drop-path.js', import.meta.url))

function runBench (args) {
  return new Promise((resolve, reject) => {
    execFile(process.execPath, [BENCH, ...args], { timeout: 120_000 }, (error, stdout, stderr) => {
      if (error) reject(new Error(`${error.message}\n${stderr}`))
      else resolve(stdout)
    })
  })
}

// The bench drives the real server code through its own wiring (Connection,
// Arena, store): a change to one of their constructors must not leave it broken.
describe('bench/drop-path.js', () => {
  it('runs the real drop path in both deliveries and accounts for every drop', async () => {
    for (const delivery of ['seeds', 'snapshots']) {
      const report = JSON.parse(await runBench(['--drops', '200', '--rooms', '3', '--delivery', delivery, '--json']))
      expect(report.drops).toBe(200)
      expect(report.settled).toBeGreaterThan(0)
      expect(report.totalPerDrop).toBeGreaterThan(0)
      expect(Object.keys(report.perDrop)).toContain('physics (room steps, landings)')
    }
  }, 120_000)
})
