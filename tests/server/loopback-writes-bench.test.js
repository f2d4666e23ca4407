import { describe, it, expect } from 'vitest'
import { execFile } from 'node:child_process'
import { fileURLToPath } from 'node:url'

const BENCH = fileURLToPath(new URL('../../bench/loopback-writes.js', import.meta.url))

function runBench (args) {
  return new Promise((resolve) => {
    execFile(process.execPath, [BENCH, ...args], { timeout: 60_000 }, (error, stdout, stderr) => resolve({ code: error ? error.code : 0, stdout, stderr }))
  })
}

// The figures RESULTS cites for a write's cost in the kernel come from this
// bench: it must keep running, and print each way's CPU per frame.
describe('bench/loopback-writes.js', () => {
  it('writes every socket both ways and prints the CPU per frame of each', async () => {
    const { code, stdout, stderr } = await runBench(['--sockets', '20', '--per-tick', '10', '--ticks', '3', '--rounds', '2'])
    expect(stderr).toBe('')
    expect(code).toBe(0)
    expect(stdout).toMatch(/^loopback writes: 20 sockets, 500-byte frames/)
    const rounds = stdout.split('\n').filter((line) => line.startsWith('round '))
    expect(rounds).toHaveLength(2)
    for (const line of rounds) expect(line).toMatch(/not steered: as the server writes \(10 a tick\) user \d+\.\d\d, system \d+\.\d\d µs a frame; back to back user \d+\.\d\d, system \d+\.\d\d µs a frame$/)
  }, 60_000)

  it('refuses a count that is not a positive integer, with its usage and exit code 2', async () => {
    const { code, stderr } = await runBench(['--sockets', '0'])
    expect(code).toBe(2)
    expect(stderr).toMatch(/^usage: node bench\/loopback-writes.js/)
  })
})
