import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import net from 'node:net'
import WebSocket from 'ws'
import { storeBackend } from '../server/helpers/stores.js'
import { GameClient } from '../server/helpers/game-client.js'
import { startServerProcess } from './helpers/server-process.js'
import { expectConsistentLedger } from './helpers/ledger.js'

/**
 * SIGTERM on a real server process with balls in flight: it stops taking
 * work, plays every ball to the end, commits and announces the settlements,
 * closes every socket with 1001 and exits 0 within a bound; its last log
 * line says so (drops settled, sockets closed, exit code).
 */
const EXIT_BOUND_MS = 15_000

/**
 * The server's last log line (JSON: the output is piped), once its pipes
 * have closed (`pipesClosed`: the child's 'close', listened for before the
 * signal; 'exit' can come before the last chunk is read).
 */
async function lastLogLine (proc, pipesClosed) {
  await pipesClosed
  return JSON.parse(proc.output().trimEnd().split('\n').at(-1))
}

describe('graceful shutdown (SIGTERM) on sqlite', () => {
  const backend = storeBackend('sqlite')
  beforeAll(async () => { await backend.setup() })
  afterAll(async () => { await backend.teardown() })

  it('settles what is in flight, closes sockets with 1001 and exits 0 in time', async () => {
    const db = await backend.newDatabase()
    const proc = startServerProcess(db.url, { DROP_RATE: '100', DROP_BURST: '100' })
    const port = await proc.port
    const players = []
    for (const room of ['16-high', '12-low', '9-medium']) {
      const session = await (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
      const client = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
      client.send({ type: 'join', room })
      await client.take('joined')
      players.push({ session, client })
    }
    for (const { client } of players) for (let i = 0; i < 40; i++) client.send({ type: 'drop', bet: 10 + i })
    for (const { client } of players) for (let i = 0; i < 40; i++) await client.take('dropped')
    const acked = players.flatMap(({ client }) => client.messages.filter((m) => m.type === 'dropped' && m.player === client.welcome.playerId))
    const settledEarly = players.reduce((n, { client }) => n + client.messages.filter((m) => m.type === 'settled' && m.player === client.welcome.playerId).length, 0)
    expect(settledEarly).toBeLessThan(acked.length)

    const started = Date.now()
    const pipesClosed = new Promise((resolve) => proc.child.once('close', resolve))
    proc.child.kill('SIGTERM')
    // Work sent once shutdown has begun is refused (or never reaches a handler); nothing is debited for it.
    while (!/shutting down/.test(proc.output())) await new Promise((resolve) => setTimeout(resolve, 2))
    for (const { client } of players) if (client.socket.readyState === WebSocket.OPEN) client.send({ type: 'drop', bet: 1, ref: 'late' })
    const exit = await Promise.race([proc.exited, new Promise((resolve) => setTimeout(() => resolve('timeout'), EXIT_BOUND_MS))])
    expect(exit).toEqual({ code: 0, signal: null })
    console.info(`[graceful-shutdown] ${acked.length} drops acknowledged, ${acked.length - settledEarly} in flight at SIGTERM; exited 0 after ${Date.now() - started} ms`)
    // The last line says it finished: every drop in flight settled, every socket closed, and the exit code.
    const last = await lastLogLine(proc, pipesClosed)
    expect(last).toMatchObject({ level: 30, signal: 'SIGTERM', exitCode: 0, dropsUnsettled: 0, socketsClosed: players.length, socketsOpen: 0 })
    expect(last.dropsSettled).toBeGreaterThan(0)
    expect(last.dropsSettled).toBeLessThanOrEqual(acked.length - settledEarly)
    expect(last.msg).toBe(`shut down: ${last.dropsSettled} drops in flight settled, ${players.length} sockets closed; exit code 0`)
    expect(last.durationMs).toBeLessThanOrEqual(Date.now() - started)

    for (const { client, session } of players) {
      const closed = await client.closed
      expect(closed.code).toBe(1001)
      const mine = client.messages.filter((m) => m.player === session.playerId)
      const dropped = mine.filter((m) => m.type === 'dropped').map((m) => m.dropId)
      const settled = mine.filter((m) => m.type === 'settled').map((m) => m.dropId)
      expect(settled.sort()).toEqual(dropped.sort())
      for (const late of client.messages.filter((m) => m.ref === 'late')) expect(late).toMatchObject({ type: 'error', code: 'E_UNAVAILABLE' })
    }
    const ledger = await expectConsistentLedger(expect, backend, db.database, { playerIds: players.map((p) => p.session.playerId), startingBalance: 100000 })
    expect(ledger.size).toBe(acked.length)
    // And the port is closed.
    const refused = await new Promise((resolve) => {
      const socket = new WebSocket(`ws://127.0.0.1:${port}/ws`)
      socket.once('error', () => resolve(true))
      socket.once('open', () => { socket.terminate(); resolve(false) })
    })
    expect(refused).toBe(true)
  })

  it('refuses new connections while closing', async () => {
    const db = await backend.newDatabase()
    const proc = startServerProcess(db.url)
    const port = await proc.port
    const session = await (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
    const client = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
    client.send({ type: 'join', room: '16-high' })
    await client.take('joined')
    client.send({ type: 'drop', bet: 5 })
    await client.take('dropped')
    proc.child.kill('SIGTERM')
    while (!/shutting down/.test(proc.output())) await new Promise((resolve) => setTimeout(resolve, 5))
    // Whatever the moment, a newcomer is never admitted: refused, 503, or E_UNAVAILABLE + 1001.
    const outcome = await new Promise((resolve) => {
      const late = new WebSocket(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
      const messages = []
      late.on('message', (data) => messages.push(JSON.parse(data.toString())))
      late.once('unexpected-response', (req, res) => { res.destroy(); resolve({ status: res.statusCode }) })
      late.once('error', () => resolve({ refused: true }))
      late.once('close', (code) => resolve({ code, messages }))
    })
    if (outcome.code !== undefined) {
      expect(outcome.code).toBe(1001)
      expect(outcome.messages.some((m) => m.type === 'welcome')).toBe(false)
    } else if (outcome.status !== undefined) {
      expect(outcome.status).toBe(503)
    }
    expect(await proc.exited).toEqual({ code: 0, signal: null })
    await client.closed
  })
  it('exits within SHUTDOWN_TIMEOUT_MS even when a client holds a request open, with everything settled', async () => {
    const db = await backend.newDatabase()
    const proc = startServerProcess(db.url, { SHUTDOWN_TIMEOUT_MS: '1500' })
    const port = await proc.port
    const session = await (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
    const client = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
    client.send({ type: 'join', room: '16-high' })
    await client.take('joined')
    for (let i = 0; i < 10; i++) client.send({ type: 'drop', bet: 3 })
    for (let i = 0; i < 10; i++) await client.take('dropped')
    // Slowloris: half a request, never finished.
    const slow = net.connect(port, '127.0.0.1')
    slow.on('error', () => {})
    await new Promise((resolve) => slow.once('connect', resolve))
    slow.write('PUT /api/seeds/client HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{"cl')
    await new Promise((resolve) => setTimeout(resolve, 100))
    const started = Date.now()
    const pipesClosed = new Promise((resolve) => proc.child.once('close', resolve))
    proc.child.kill('SIGTERM')
    const exit = await Promise.race([proc.exited, new Promise((resolve) => setTimeout(() => resolve('timeout'), EXIT_BOUND_MS))])
    expect(exit).not.toBe('timeout')
    expect([0, 1]).toContain(exit.code)
    expect(Date.now() - started).toBeLessThan(EXIT_BOUND_MS)
    // Whichever way it ended, the last line says so, with the real exit code; the drops were settled either way.
    const last = await lastLogLine(proc, pipesClosed)
    expect(last).toMatchObject({ signal: 'SIGTERM', exitCode: exit.code, dropsUnsettled: 0, socketsOpen: 0 })
    expect(last.msg).toMatch(exit.code === 0
      ? /^shut down: \d+ drops? in flight settled, 1 socket closed; exit code 0$/
      : /^graceful shutdown timed out after 1500 ms: \d+ drops? in flight settled, 1 socket closed; exit code 1$/)
    expect((await client.closed).code).toBe(1001)
    expect(client.messages.filter((m) => m.type === 'settled')).toHaveLength(10)
    await expectConsistentLedger(expect, backend, db.database, { playerIds: [session.playerId], startingBalance: 100000 })
    slow.destroy()
  })
})
