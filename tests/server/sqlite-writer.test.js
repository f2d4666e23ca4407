import { describe, it, expect, beforeEach, afterEach } from 'vitest'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { DatabaseSync } from 'node:sqlite'
import { Worker } from 'node:worker_threads'
import { SqliteStore } from '../../server/store/sqlite-store.js'
import { WRITER_THREAD_NICE } from '../../server/store/sqlite-store.js'
import { prepareWrites, transactionGroups, MAX_WRITES_PER_TRANSACTION } from '../../server/store/sqlite-writer-thread.js'
import { MIGRATIONS } from '../../server/store/migrations.js'
import { threadNices } from '../helpers/thread-nices.js'

/**
 * The SQLite store commits the tick's batches on a writer thread with its
 * own connection (server/store/sqlite-store.js, sqlite-writer-thread.js): what it reports committed
 * is in the file, a failed batch leaves nothing behind, close() waits for
 * what was sent, and a thread that dies is replaced.
 */
let dir, file, store

beforeEach(async () => {
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-writer-'))
  file = path.join(dir, 'ledger.sqlite')
  store = new SqliteStore({ file, checkpointIntervalMs: 100 })
  await store.migrate()
  await store.createPlayer({ id: 'p1', tokenHash: 'h1', balance: 1000, clientSeed: 'c', createdAt: 1, seed: { id: 's1', seed: 'a'.repeat(64), hash: 'b'.repeat(64) } })
})

afterEach(async () => {
  await store.close()
  fs.rmSync(dir, { recursive: true, force: true })
})

const drop = (id) => ({ id, playerId: 'p1', room: '8-low', rows: 8, risk: 'low', engineVersion: '1.0.0', serverSeedId: 's1', serverSeedHash: 'b'.repeat(64), clientSeed: 'c', nonce: id, dropSeed: 'd'.repeat(64), bet: 10, payoutRule: 2, startTick: 0, createdAt: 2 })
const batch = (drops, settlements = [], balances = []) => ({ drops, settlements, balances, clientSeeds: [] })
/** What the database file holds without its WAL: a copy of the file alone, read. */
const databaseFileAlone = (sql) => {
  const copy = path.join(dir, 'alone.sqlite')
  fs.copyFileSync(file, copy)
  const db = new DatabaseSync(copy, { readOnly: true })
  try { return db.prepare(sql).all() } finally { db.close(); fs.rmSync(copy) }
}
/** Transactions committed in the WAL: its frames whose header names the database's size after a commit (bytes 4-7, 0 in every other frame). */
const walCommits = () => {
  const wal = fs.readFileSync(`${file}-wal`)
  const pageSize = wal.readUInt32BE(8)
  let commits = 0
  for (let at = 32; at + 24 + pageSize <= wal.length; at += 24 + pageSize) if (wal.readUInt32BE(at + 4) !== 0) commits++
  return commits
}
const player = (n, hash = `${n}`.padStart(64, 'f')) => ({ id: `p-${n}`, tokenHash: `t-${n}`, balance: 1000, clientSeed: 'c', createdAt: 1, seed: { id: `s-${n}`, seed: 'a'.repeat(64), hash } })
/** Reads the file through a connection of its own, as another process would. */
const read = (sql) => { const db = new DatabaseSync(file, { readOnly: true }); try { return db.prepare(sql).all() } finally { db.close() } }

describe('SQLite writer thread', () => {
  it('commits on a thread of its own, durably: another connection sees the rows once the promise resolves', async () => {
    await store.commitBatch(batch([drop(1), drop(2)], [], [{ playerId: 'p1', delta: -20 }]))
    expect(store._writer.worker).not.toBeNull()
    expect(read('SELECT id, status FROM drops ORDER BY id')).toEqual([{ id: 1, status: 'in_flight' }, { id: 2, status: 'in_flight' }])
    expect(read("SELECT balance FROM players WHERE id = 'p1'")).toEqual([{ balance: 980 }])
    // The store's own connection reads what the thread wrote.
    expect((await store.listInFlightDrops()).map((d) => d.id)).toEqual([1, 2])
  })

  it.runIf(fs.existsSync('/proc/thread-self'))('runs below the event loop\'s priority, and only its two threads (writer, checkpoint) do', async () => {
    const thisThread = Number(fs.readlinkSync('/proc/thread-self').split('/').pop())
    const before = threadNices().get(thisThread)
    await store.commitBatch(batch([drop(1)]))
    await store.checkpointer.nextCheckpoint()
    const nices = threadNices()
    expect([...nices.values()].filter((nice) => nice === WRITER_THREAD_NICE)).toHaveLength(2)
    expect(nices.get(thisThread)).toBe(before)
    expect(before).not.toBe(WRITER_THREAD_NICE)
  })

  it('rejects a failing batch with its error and leaves none of it written', async () => {
    await store.commitBatch(batch([drop(1)]))
    const settle = { id: 99, bucket: 1, multiplier: 1, payout: 10, ticks: 100, stateHash: '0'.repeat(16), settledAt: 3 }
    await expect(store.commitBatch(batch([drop(2)], [settle], [{ playerId: 'p1', delta: 10 }]))).rejects.toThrow(/drop 99 is not in flight/)
    expect(read('SELECT id FROM drops')).toEqual([{ id: 1 }])
    expect(read("SELECT balance FROM players WHERE id = 'p1'")).toEqual([{ balance: 1000 }])
    // The next batch goes through.
    await store.commitBatch(batch([drop(3)]))
    expect(read('SELECT id FROM drops ORDER BY id')).toEqual([{ id: 1 }, { id: 3 }])
  })

  it('never checkpoints in a commit: the WAL grows past SQLite\'s default 1,000 pages with nothing copied', async () => {
    await store.close()
    store = new SqliteStore({ file, checkpointIntervalMs: 3_600_000 })
    const walPages = () => (fs.statSync(`${file}-wal`).size - 32) / (4096 + 24)
    for (let id = 1; walPages() <= 1200; id++) {
      expect(id, 'the WAL grows past 1,200 pages').toBeLessThan(2000)
      await store.commitBatch(batch([{ ...drop(id), nonce: id }]))
    }
    // Had a commit checkpointed at 1,000 pages, the next would have started the WAL over from its first page.
    expect(walPages()).toBeGreaterThan(1200)
    expect(databaseFileAlone('SELECT COUNT(*) AS n FROM drops')).toEqual([{ n: 0 }])
    expect(read('SELECT COUNT(*) AS n FROM drops')[0].n).toBeGreaterThan(100)
  })

  it('copies the WAL into the database on its checkpoint thread, and the next commits reuse the WAL from its start', async () => {
    await store.close()
    store = new SqliteStore({ file, checkpointIntervalMs: 50 })
    for (let id = 1; id <= 200; id++) await store.commitBatch(batch([{ ...drop(id), nonce: id }]))
    // A checkpoint that ran while commits came in may have stopped short of the last: the next one, with none coming, copies all.
    await store.checkpointer.nextCheckpoint()
    const outcome = await store.checkpointer.nextCheckpoint()
    expect(outcome.busy).toBe(0)
    expect(outcome.walPages).toBeGreaterThan(0)
    expect(outcome.copiedPages).toBe(outcome.walPages)
    // The database file alone, without its WAL, now holds every committed drop.
    expect(databaseFileAlone('SELECT COUNT(*) AS n FROM drops')).toEqual([{ n: 200 }])
    const walBytes = fs.statSync(`${file}-wal`).size
    for (let id = 201; id <= 210; id++) await store.commitBatch(batch([{ ...drop(id), nonce: id }]))
    expect(fs.statSync(`${file}-wal`).size, 'the WAL was started over, not grown').toBe(walBytes)
    expect(read('SELECT COUNT(*) AS n FROM drops')).toEqual([{ n: 210 }])
  })

  it('keeps the WAL from growing while commits come in during every pass: after each, the writer copies what came in', async () => {
    await store.close()
    store = new SqliteStore({ file, checkpointIntervalMs: 3_600_000 })
    const finished = []
    const finish = store.checkpointer.finish
    store.checkpointer.finish = () => { finished.push(store.checkpointer.last); finish() }
    const walPages = () => (fs.statSync(`${file}-wal`).size - 32) / (4096 + 24)
    let id = 1
    const commits = async (n) => { for (let k = 0; k < n; k++, id++) await store.commitBatch(batch([{ ...drop(id), nonce: id }])) }
    await commits(20)
    for (let cycle = 0; cycle < 30; cycle++) {
      // A pass, and commits while it runs, then more before the next one.
      await Promise.all([store.checkpointer.checkpointNow(), commits(5)])
      await commits(15)
    }
    expect(finished).toHaveLength(30)
    // Each commit writes at least three pages (the drop's, its index's, the nonce's): 620 commits, never
    // started over, would leave the WAL at 1,860 pages or more; started over after each pass, about a cycle's.
    expect(walPages()).toBeLessThan(400)
    expect(read('SELECT COUNT(*) AS n FROM drops')).toEqual([{ n: id - 1 }])
  })

  it('starts the writer only where the store asked for it: imported by another thread (an in-memory store), its file runs nothing', async () => {
    const url = new URL('../../server/store/sqlite-writer-thread.js', import.meta.url).href
    const code = `const { parentPort } = require('node:worker_threads')
      import(${JSON.stringify(url)}).then((m) => parentPort.postMessage({ listeners: parentPort.listenerCount('message'), writes: m.WRITES }))`
    const worker = new Worker(code, { eval: true, workerData: { something: 'else' } })
    const reply = await new Promise((resolve, reject) => { worker.once('message', resolve); worker.once('error', reject) })
    await worker.terminate()
    expect(reply).toEqual({ listeners: 0, writes: ['commitBatch', 'createPlayer', 'rotateSeed', 'checkpoint'] })
    // The in-memory store runs the same transactions on its own connection.
    const memory = new SqliteStore({ file: ':memory:' })
    await memory.migrate()
    await memory.createPlayer({ id: 'p1', tokenHash: 'h1', balance: 1000, clientSeed: 'c', createdAt: 1, seed: { id: 's1', seed: 'a'.repeat(64), hash: 'b'.repeat(64) } })
    await memory.commitBatch(batch([drop(1)], [], [{ playerId: 'p1', delta: -10 }]))
    expect(memory._writer).toBeNull()
    expect((await memory.loadAccount('p1')).balance).toBe(990)
    await memory.close()
  })

  it('close() waits for the batches already sent', async () => {
    const pending = store.commitBatch(batch([drop(1), drop(2), drop(3)]))
    await store.close()
    await pending
    expect(read('SELECT count(*) AS n FROM drops')).toEqual([{ n: 3 }])
    store = new SqliteStore({ file }) // for afterEach
  })

  it('settles what a dead thread held, then starts a new one', async () => {
    await store.commitBatch(batch([drop(1)]))
    const first = store._writer.worker
    const pending = store.commitBatch(batch([drop(2)]))
    await first.terminate()
    // Killed before or after its commit: the promise settles either way, never hangs,
    // and a batch reported committed is in the file.
    const outcome = await pending.then(() => 'committed', (error) => error.message)
    if (outcome === 'committed') expect(read('SELECT id FROM drops').map((r) => r.id)).toContain(2)
    else expect(outcome).toMatch(/exited/)
    await store.commitBatch(batch([drop(3)]))
    expect(store._writer.worker).not.toBe(first)
    expect(read('SELECT id FROM drops ORDER BY id').map((r) => r.id)).toContain(3)
  })

  it('puts the writes that wait while it is busy in one transaction: 200 sign-ups at once are a few commits, a failing one undone alone', async () => {
    await store.close()
    store = new SqliteStore({ file, checkpointIntervalMs: 3_600_000 })
    await store.commitBatch(batch([drop(1)]))
    const before = walCommits()
    const signUps = Array.from({ length: 200 }, (_, n) => store.createPlayer(n === 100 ? player(n, 'b'.repeat(64)) : player(n)))
    const tick = store.commitBatch(batch([drop(2)], [], [{ playerId: 'p1', delta: -10 }]))
    const outcomes = await Promise.allSettled([...signUps, tick])
    // The one whose seed's hash is taken (UNIQUE) fails with SQLite's code; the others and the batch are durable.
    expect(outcomes.filter((o) => o.status === 'rejected').map((o) => o.reason.code)).toEqual(['SQLITE_CONSTRAINT'])
    expect(outcomes[100].status).toBe('rejected')
    expect(read("SELECT COUNT(*) AS n FROM players WHERE id LIKE 'p-%'")).toEqual([{ n: 199 }])
    // Its player row went with its savepoint: nothing half-written.
    expect(read("SELECT COUNT(*) AS n FROM players WHERE id = 'p-100'")).toEqual([{ n: 0 }])
    expect(read('SELECT id FROM drops ORDER BY id').map((r) => r.id)).toEqual([1, 2])
    expect(read("SELECT balance FROM players WHERE id = 'p1'")).toEqual([{ balance: 990 }])
    // One commit each would be 201; the thread wakes for more than one message at a time.
    expect(walCommits() - before).toBeLessThan(50)
  })
})

describe("the writer's transactions", () => {
  const memory = () => {
    const db = new DatabaseSync(':memory:')
    for (const migration of MIGRATIONS) db.exec(migration.sql)
    return db
  }

  it('together(): each write in a savepoint, one that throws undone alone, the rest committed in one transaction', () => {
    const db = memory()
    const writes = prepareWrites(db)
    writes.createPlayer(player(0))
    const outcomes = writes.together([
      { op: 'createPlayer', args: player(1) },
      { op: 'createPlayer', args: player(2, player(0).seed.hash) }, // the player row goes in, its seed's hash is taken
      { op: 'rotateSeed', args: { playerId: 'p-1', oldSeedId: 's-1', newSeed: { id: 's-1b', seed: 'e'.repeat(64), hash: 'e'.repeat(64) }, at: 5 } },
      { op: 'rotateSeed', args: { playerId: 'p-0', oldSeedId: 'nope', newSeed: { id: 's-0b', seed: 'e'.repeat(64), hash: 'd'.repeat(64) }, at: 5 } },
      { op: 'commitBatch', args: { drops: [], settlements: [], balances: [{ playerId: 'p-1', delta: 5 }], clientSeeds: [], players: ['p-1'] } }
    ])
    expect(outcomes.map((o) => ('error' in o ? o.error.code ?? o.error.message : 'ok'))).toEqual(['ok', 'SQLITE_CONSTRAINT', 'ok', 'seed nope is not the active seed of p-0', 'ok'])
    expect(outcomes[4].result.balances.get('p-1')).toBe(1005)
    expect(db.isTransaction).toBe(false)
    expect(db.prepare('SELECT id FROM players ORDER BY id').all().map((r) => r.id)).toEqual(['p-0', 'p-1'])
    expect(db.prepare('SELECT id, active FROM server_seeds ORDER BY id').all().map((r) => `${r.id}:${r.active}`)).toEqual(['s-0:1', 's-1:0', 's-1b:1'])
    db.close()
  })

  it('together(): a transaction it cannot open fails every write of the group with the reason', () => {
    const db = memory()
    const writes = prepareWrites(db)
    db.exec('BEGIN') // already in one: BEGIN IMMEDIATE fails
    const outcomes = writes.together([{ op: 'createPlayer', args: player(1) }, { op: 'createPlayer', args: player(2) }])
    db.exec('ROLLBACK')
    expect(outcomes).toHaveLength(2)
    for (const outcome of outcomes) expect(outcome.error.message).toMatch(/within a transaction/)
    expect(db.prepare('SELECT COUNT(*) AS n FROM players').get().n).toBe(0)
    db.close()
  })

  it('transactionGroups(): runs of writes in order, a checkpoint or unknown write alone, none longer than the cap', () => {
    const m = (op, id) => ({ op, id })
    const ops = (groups) => groups.map((g) => g.map((x) => x.id))
    expect(ops(transactionGroups([m('createPlayer', 1), m('commitBatch', 2), m('checkpoint', 3), m('rotateSeed', 4), m('createPlayer', 5), m('nonsense', 6), m('createPlayer', 7)])))
      .toEqual([[1, 2], [3], [4, 5], [6], [7]])
    const many = Array.from({ length: MAX_WRITES_PER_TRANSACTION * 2 + 1 }, (_, i) => m('createPlayer', i))
    expect(transactionGroups(many).map((g) => g.length)).toEqual([MAX_WRITES_PER_TRANSACTION, MAX_WRITES_PER_TRANSACTION, 1])
    expect(transactionGroups(many).flat()).toEqual(many)
    expect(transactionGroups([])).toEqual([])
  })
})
