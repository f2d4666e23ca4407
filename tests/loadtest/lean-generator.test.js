import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import http from 'node:http'
import { once } from 'node:events'
import { WebSocketServer } from 'ws'
import { startServer } from '../../loadtest/driver/server-process.js'
import { runLeanLoad, formatLeanSummary, quantile, laggiest } from '../../loadtest/lean/lean-generator.js'
import { parseLeanArgs } from '../../loadtest/lean/run.js'
import { encodeSnapshot, encodeRoomFrame } from '../../protocol/snapshot-codec.js'

describe('lean load generator against the real server', () => {
  let server
  let dir
  beforeAll(async () => {
    dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-lean-test-'))
    server = await startServer({ dataDir: dir, logFile: path.join(dir, 'server.log') })
  })
  afterAll(async () => {
    await server?.stop()
    fs.rmSync(dir, { recursive: true, force: true })
  })

  it('plays every player to the end with every check passing, and prints its figures', async () => {
    const summary = await runLeanLoad({ baseUrl: server.url, players: 30, rooms: 6, durationS: 4, rampS: 1, dropIntervalMs: 500, drainS: 10, workers: 2 })
    expect(summary.failures).toEqual([])
    expect(summary.passed).toBe(true)
    expect(summary.joined).toBe(30)
    expect(summary.rooms).toBe(6)
    expect(summary.errorCount).toBe(0)
    expect(summary.dropsSent).toBeGreaterThan(30)
    expect(summary.dropsAcked).toBe(summary.dropsSent)
    expect(summary.dropsSettled).toBe(summary.dropsSent)
    expect(summary.unsettled).toBe(0)
    expect(summary.ackMs.count).toBe(summary.dropsSent)
    expect(summary.settledMs.count).toBe(summary.dropsSent)
    // Drops sent in the steady window are timed apart from the ramp's.
    expect(summary.steady.ackMs.count).toBeGreaterThan(0)
    expect(summary.steady.ackMs.count).toBeLessThan(summary.dropsSent)
    // The room frames arrive (20 Hz snapshots) and the generator's own CPU is measured.
    expect(summary.window.frames).toBeGreaterThan(0)
    expect(summary.window.framesPerSecondPerPlayer).toBeGreaterThan(0)
    expect(summary.cpu.usPerFrame).toBeGreaterThan(0)
    expect(summary.cpu.perWorker).toHaveLength(2)
    const text = formatLeanSummary(summary)
    expect(text).toContain('30 players (30 joined) in 6 rooms, 2 worker threads')
    expect(text).toContain(': PASS')
    expect(text).toMatch(/drop → dropped p50 \/ p99: [\d.]+ \/ [\d.]+ ms/)
    expect(text).toMatch(/drop → settled p50 \/ p99: \d+ \/ \d+ ms/)
    expect(text).toMatch(/per player: [\d.]+ frames\/s, [\d.]+ KB\/s payload/)
    expect(text).toMatch(/generator CPU: [\d.]+ µs per frame received/)
    // How late each worker's event loop ran over the window: every latency it timed includes that.
    for (const worker of summary.cpu.perWorker) {
      expect(worker.loopDelay.p50Ms).toBeGreaterThanOrEqual(0)
      expect(worker.loopDelay.p99Ms).toBeGreaterThanOrEqual(worker.loopDelay.p50Ms)
      expect(worker.loopDelay.maxMs).toBeGreaterThanOrEqual(worker.loopDelay.p99Ms)
    }
    expect(summary.cpu.loopDelay).toBe(laggiest(summary.cpu.perWorker))
    expect(text).toMatch(/generator event loop late by p50 \/ p99 \/ max [\d.]+ \/ [\d.]+ \/ \d+ ms/)
  })

  it('names the worker whose event loop ran latest at p99, and none without figures', () => {
    const a = { p50Ms: 1, p99Ms: 4, maxMs: 9 }
    const b = { p50Ms: 2, p99Ms: 12, maxMs: 15 }
    expect(laggiest([{ loopDelay: a }, { loopDelay: b }, { loopDelay: null }])).toBe(b)
    expect(laggiest([{ loopDelay: null }])).toBeNull()
    expect(laggiest([])).toBeNull()
  })

  it('plays seeds mode: no positions, the other players\' drops decoded from drop-events frames and timed', async () => {
    const summary = await runLeanLoad({ baseUrl: server.url, players: 20, rooms: 2, durationS: 3, rampS: 1, dropIntervalMs: 500, drainS: 10, workers: 2, delivery: 'seeds' })
    expect(summary.failures).toEqual([])
    expect(summary.delivery).toBe('seeds')
    expect(summary.errorCount).toBe(0) // a snapshot frame would be X_UNEXPECTED_SNAPSHOT
    expect(summary.dropsSettled).toBe(summary.dropsSent)
    expect(summary.eventFrames).toBeGreaterThan(0)
    // Each drop reaches the 9 other players of its room.
    expect(summary.eventsSeen).toBeGreaterThan(summary.dropsSent)
    expect(summary.steady.sightingMs.count).toBeGreaterThan(0)
    expect(summary.steady.sightingMs.p99).toBeGreaterThan(0)
    // Carried by the room's next frame on its 4 Hz grid (every 15 ticks), held at most half a
    // period (7 ticks) for a commit and a tick or two more: room ticks, whatever the machine's load.
    expect(summary.steady.sightingTicks.p50).toBeGreaterThanOrEqual(0)
    expect(summary.steady.sightingTicks.p99).toBeLessThanOrEqual(15 + 7 + 2)
    const text = formatLeanSummary(summary)
    expect(text).toContain('lean generator (seeds delivery): 20 players')
    expect(text).toMatch(/sent → seen by the room p50 \/ p99: [\d.]+ \/ [\d.]+ ms \(\d+ sightings in the steady window\), carried by a frame p50 \/ p99 \d+ \/ \d+ ticks after the ball's release/)
  })

  it('refuses a target that is not on this machine', async () => {
    await expect(runLeanLoad({ baseUrl: 'http://10.0.0.1:8080', players: 1, rooms: 1, durationS: 1 })).rejects.toThrow(/not on this machine/)
  })
})

/**
 * A fake game server that gets one thing wrong: its `settled` balance is
 * 1 milli-credit off. The generator must fail the run with X_BALANCE_MISMATCH.
 */
async function lyingServer () {
  const httpServer = http.createServer((request, response) => {
    if (request.method === 'POST' && request.url === '/api/session') {
      response.writeHead(201, { 'content-type': 'application/json' }).end(JSON.stringify({ token: `t${Math.random()}` }))
    } else if (request.url === '/api/rooms') {
      response.writeHead(200, { 'content-type': 'application/json' }).end(JSON.stringify({ roomIds: ['8-low'] }))
    } else {
      response.writeHead(404).end()
    }
  })
  const wss = new WebSocketServer({ server: httpServer, perMessageDeflate: false })
  let next = 0
  wss.on('connection', (ws) => {
    const playerId = `p${++next}`
    let balance = 1000
    let tick = 0
    const timer = setInterval(() => ws.send(encodeRoomFrame('[]', encodeSnapshot(tick += 3, new Uint8Array(0), 0, new Float64Array(0), new Float64Array(0))), { binary: true }), 50)
    ws.on('close', () => clearInterval(timer))
    ws.send(JSON.stringify({ type: 'welcome', playerId, balance }))
    ws.on('message', (data) => {
      const message = JSON.parse(data.toString())
      if (message.type === 'join') ws.send(JSON.stringify({ type: 'joined', room: message.room, snapshotEvery: 3 }))
      if (message.type === 'drop') {
        const dropId = `${playerId}-${message.ref}`
        balance -= message.bet
        ws.send(JSON.stringify({ type: 'dropped', player: playerId, ref: message.ref, dropId, bet: message.bet, balance }))
        setTimeout(() => {
          balance += message.bet * 2
          ws.send(JSON.stringify({ type: 'settled', player: playerId, dropId, bet: message.bet, multiplier: 2, payout: message.bet * 2, ticks: 30, balance: balance + 0.001 }))
        }, 100)
      }
    })
  })
  httpServer.listen(0, '127.0.0.1')
  await once(httpServer, 'listening')
  return {
    url: `http://127.0.0.1:${httpServer.address().port}`,
    close: () => {
      for (const client of wss.clients) client.terminate()
      return new Promise((resolve) => httpServer.close(resolve))
    }
  }
}

describe('lean load generator checks', () => {
  it('fails a run whose server sends a balance that does not follow', async () => {
    const fake = await lyingServer()
    try {
      const summary = await runLeanLoad({ baseUrl: fake.url, players: 3, rooms: 1, durationS: 1.5, rampS: 0.2, dropIntervalMs: 300, drainS: 2 })
      expect(summary.passed).toBe(false)
      expect(summary.errors.X_BALANCE_MISMATCH).toBeGreaterThan(0)
      expect(summary.balanceMismatches).toBe(summary.errors.X_BALANCE_MISMATCH)
      expect(summary.dropsSettled).toBe(summary.dropsSent)
      expect(formatLeanSummary(summary)).toContain('FAIL')
    } finally {
      await fake.close()
    }
  })
})

describe('lean generator figures and options', () => {
  it('takes nearest-rank quantiles', () => {
    expect(quantile([5, 1, 4, 2, 3], 0.5)).toBe(3)
    expect(quantile(Float64Array.from({ length: 100 }, (_, i) => i + 1), 0.99)).toBe(99)
    expect(quantile([], 0.5)).toBeNull()
  })

  it('reads its command line', () => {
    expect(parseLeanArgs(['--players', '3000', '--rooms', '100', '--duration', '60s', '--drop-interval', '2s', '--workers', '2', '--pin'])).toMatchObject({
      players: 3000, rooms: 100, durationS: 60, dropIntervalMs: 2000, workers: 2, pin: true, delivery: 'snapshots'
    })
    expect(parseLeanArgs(['--delivery', 'seeds'])).toMatchObject({ delivery: 'seeds' })
    expect(() => parseLeanArgs(['--delivery', 'positions'])).toThrow(/--delivery must be one of snapshots, seeds/)
    expect(parseLeanArgs([])).toMatchObject({ players: 100, rooms: 100, durationS: 30, rampS: 10, dropIntervalMs: 2000, bet: 10, workers: 1, pin: false })
    expect(() => parseLeanArgs(['--players', '0'])).toThrow(/positive integer/)
  })
})
