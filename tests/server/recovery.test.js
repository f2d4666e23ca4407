import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { spawn } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { createBoard, simulateDrop } from '../../engine/index.js'
import { openStore } from '../../server/store/open-store.js'
import { settleInterruptedDrops } from '../../server/game/recovery.js'
import { STORE_KINDS, storeBackend } from './helpers/stores.js'
import { startServer, OPERATOR_TOKEN } from './helpers/server.js'
import { GameClient } from './helpers/game-client.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')
// The ledger holds milli-credits; new drops pay bet × multiplier exactly.
const payoutMilli = (bet, multiplier) => bet * Math.round(multiplier * 1000)
const silentLog = { info () {}, warn () {}, error () {} }

/** `npm start` in a child process on a free port; resolves once it listens. */
function startServerProcess (databaseUrl) {
  const child = spawn(process.execPath, [path.join(ROOT, 'server/server.js')], {
    cwd: ROOT,
    env: { ...process.env, DATABASE_URL: databaseUrl, PORT: '0', HOST: '127.0.0.1', LOG_LEVEL: 'info', OPERATOR_TOKEN, CLIENT_DIR: '/nonexistent/plinko-client' },
    stdio: ['ignore', 'pipe', 'pipe']
  })
  const exited = new Promise((resolve) => child.once('exit', (code, signal) => resolve({ code, signal })))
  const port = new Promise((resolve, reject) => {
    let output = ''
    const onData = (chunk) => {
      output += chunk
      const match = /listening at http:\/\/127\.0\.0\.1:(\d+)/.exec(output)
      if (match) resolve(Number(match[1]))
    }
    child.stdout.on('data', onData)
    child.stderr.on('data', onData)
    exited.then(() => reject(new Error(`server exited before listening:\n${output}`)))
  })
  return { child, port, exited }
}

describe.each(STORE_KINDS)('recovery and persistence on %s', (kind) => {
  const backend = storeBackend(kind)

  beforeAll(async () => { await backend.setup() })
  afterAll(async () => { await backend.teardown() })

  it('settles drops left in flight by a killed server from their seeds at the next start, and keeps sessions', async () => {
    const db = await backend.newDatabase()
    const proc = startServerProcess(db.url)
    let session
    const dropped = []
    try {
      const port = await proc.port
      session = await (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
      const client = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
      client.send({ type: 'join', room: '16-high' })
      await client.take('joined')
      for (const bet of [100, 200, 300]) client.send({ type: 'drop', bet })
      for (let i = 0; i < 3; i++) dropped.push(await client.take('dropped'))
    } finally {
      // A crash: no graceful shutdown, no settling.
      proc.child.kill('SIGKILL')
      await proc.exited
    }

    // Precondition: the bets are recorded and debited, the drops unsettled.
    const inFlight = await backend.query(db.database, "SELECT id FROM drops WHERE status = 'in_flight' ORDER BY id")
    expect(inFlight.map((row) => Number(row.id))).toEqual(dropped.map((d) => d.dropId))
    const [debited] = await backend.query(db.database, 'SELECT balance FROM players WHERE id = $1', [session.playerId])
    expect(Number(debited.balance)).toBe((100000 - 600) * 1000)

    const server = await startServer(db)
    try {
      const rows = await backend.query(db.database, 'SELECT * FROM drops ORDER BY id')
      const board = createBoard({ rows: 16, risk: 'high' })
      let expected = 100000 * 1000
      for (const [i, row] of rows.entries()) {
        const outcome = simulateDrop(board, dropped[i].dropSeed)
        expect(row).toMatchObject({ status: 'settled', bucket: outcome.bucket, ticks: outcome.ticks, state_hash: outcome.stateHash, payout: payoutMilli(Number(row.bet), outcome.multiplier) })
        expected += Number(row.payout) - Number(row.bet) * 1000
      }
      // The session survived the crash, with the recovered balance and the nonces used.
      const me = await server.api('GET', '/api/me', { token: session.token })
      expect(me.status).toBe(200)
      expect(me.body).toMatchObject({ playerId: session.playerId, balance: expected / 1000, nonce: 3, serverSeedHash: session.serverSeedHash })
      const audit = await server.api('GET', `/api/audit/drops/${dropped[0].dropId}`, { token: OPERATOR_TOKEN })
      expect(audit.body.matches).toBe(true)
      // New drops continue after the recovered ids and nonces.
      const { client } = await server.player()
      const again = await server.connect(session.token)
      again.send({ type: 'join', room: '8-medium' })
      await again.take('joined')
      again.send({ type: 'drop', bet: 1 })
      const next = await again.take('dropped')
      expect(next.dropId).toBeGreaterThan(dropped[2].dropId)
      expect(next.nonce).toBe(3)
      await again.take('settled')
      await client.close()
    } finally {
      await server.close()
    }
  })

  it('settles every ball in flight on a graceful shutdown and closes clients with 1001', async () => {
    const db = await backend.newDatabase()
    const server = await startServer(db)
    const { client, session } = await server.player('11-high')
    for (const bet of [5, 6]) client.send({ type: 'drop', bet })
    await client.take('dropped')
    await client.take('dropped')
    await server.app.close()
    expect(client.messages.filter((m) => m.type === 'settled')).toHaveLength(2)
    expect((await client.closed).code).toBe(1001)
    const rows = await backend.query(db.database, 'SELECT status FROM drops WHERE player_id = $1', [session.playerId])
    expect(rows.map((r) => r.status)).toEqual(['settled', 'settled'])
  })

  it('leaves in flight (and reports) drops recorded under an engine version this server does not have', async () => {
    const db = await backend.newDatabase()
    const store = await openStore(db.database)
    try {
      await store.createPlayer({ id: 'p1', tokenHash: 'h'.repeat(64), balance: 90, clientSeed: 'c', createdAt: 1, seed: { id: 's1', seed: 'seed', hash: 'x'.repeat(64) } })
      const row = { playerId: 'p1', room: '8-low', rows: 8, risk: 'low', serverSeedId: 's1', serverSeedHash: 'x'.repeat(64), clientSeed: 'c', dropSeed: 'abc', bet: 5, payoutRule: 2, startTick: 0, createdAt: 2 }
      await store.commitBatch({
        drops: [{ ...row, id: 1, nonce: 0, engineVersion: '0.0.1-old' }, { ...row, id: 2, nonce: 1, engineVersion: createBoard({ rows: 8, risk: 'low' }).engineVersion }],
        settlements: [],
        balances: [],
        clientSeeds: []
      })
      expect(await settleInterruptedDrops(store, silentLog)).toEqual({ settled: 1, skipped: 1 })
      const stillInFlight = await store.listInFlightDrops()
      expect(stillInFlight.map((d) => d.id)).toEqual([1])
      const outcome = simulateDrop(createBoard({ rows: 8, risk: 'low' }), 'abc')
      expect((await store.getDrop(2))).toMatchObject({ status: 'settled', bucket: outcome.bucket, payout: payoutMilli(5, outcome.multiplier) / 1000 })
      expect((await store.loadAccount('p1')).balance).toBe(90 + payoutMilli(5, outcome.multiplier))
    } finally {
      await store.close()
    }
  })
})
