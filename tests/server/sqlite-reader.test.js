import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { DatabaseSync } from 'node:sqlite'
import { SqliteStore, READER_THREAD_NICE, WRITER_THREAD_NICE } from '../../server/store/sqlite-store.js'
import { openSqliteDatabase } from '../../server/store/sqlite-database.js'
import { threadNices } from '../helpers/thread-nices.js'

/**
 * The SQLite store's listings of drops run on a reader thread with a
 * read-only connection of its own (server/store/sqlite-reader-thread.js):
 * however many drops a listing reads, the event loop keeps turning (it
 * ticks the rooms); the thread runs below the writer's priority; one that
 * dies is replaced.
 */
const DROPS = 60_000
let dir, file, store

/** A ledger of DROPS settled drops of one player, one a millisecond (created_at = id), in 100 rooms. */
function fillLedger (target) {
  const db = new DatabaseSync(target)
  try {
    db.exec(`INSERT INTO players VALUES ('p', 't', 0, 'c', 0);
      INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES ('s', 'p', 'x', 'h', 1, 0, 0);
      WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < ${DROPS})
      INSERT INTO drops (id, player_id, room, rows, risk, engine_version, server_seed_id, server_seed_hash, client_seed, nonce, drop_seed,
        bet, bucket, multiplier, payout, start_tick, ticks, state_hash, status, created_at, settled_at, payout_rule)
      SELECT i, 'p', '16-medium.' || (i % 100), 16, 'medium', '2.0.0', 's', 'h', 'c', i, printf('%064d', i), 10, i % 17, 1.0, 10000, i, 180,
        'abcd', 'settled', i, i + 1, 2 FROM n`)
  } finally {
    db.close()
  }
}

/** Event-loop turns (setImmediate callbacks run) while `read` is pending, and its result. */
async function turnsDuring (read) {
  let turns = 0
  let waiting = true
  const spin = () => { if (waiting) { turns++; setImmediate(spin) } }
  setImmediate(spin)
  const result = await read()
  waiting = false
  return { turns, result }
}

beforeAll(async () => {
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-reader-'))
  file = path.join(dir, 'ledger.sqlite')
  store = new SqliteStore({ file })
  await store.migrate()
  fillLedger(file)
})

afterAll(async () => {
  await store?.close()
  fs.rmSync(dir, { recursive: true, force: true })
})

describe('SQLite reader thread', () => {
  // A time window alone is read through drops_created and sorted by id: its cost grows with the window.
  const window = { from: 10_000, to: 50_000, limit: 100 }
  const newestInWindow = Array.from({ length: 100 }, (_, n) => 49_999 - n)

  it('lists drops on a thread of its own: the event loop keeps turning through a listing of 40,000 drops', async () => {
    const { turns, result } = await turnsDuring(() => store.listDrops(window))
    expect(result.map((d) => d.id)).toEqual(newestInWindow)
    expect(store._reader.worker).not.toBeNull()
    expect(turns).toBeGreaterThan(0)
    // An export's pages too, in order, every match.
    const { turns: exportTurns, result: exported } = await turnsDuring(async () => {
      const ids = []
      for await (const drop of store.iterateDrops({ from: 20_000, to: 22_500 }, 1000)) ids.push(drop.id)
      return ids
    })
    expect(exported).toEqual(Array.from({ length: 2500 }, (_, n) => 20_000 + n))
    expect(exportTurns).toBeGreaterThan(0)
  })

  it('(an in-memory store, which has no second connection, runs the same listing on the event loop: no turn while it reads)', async () => {
    const memory = new SqliteStore({ file: ':memory:' })
    try {
      await memory.migrate()
      const copy = path.join(dir, 'copy.sqlite')
      const source = new DatabaseSync(file)
      source.exec(`VACUUM INTO '${copy}'`)
      source.close()
      memory.db.exec(`ATTACH '${copy}' AS filled; INSERT INTO players SELECT * FROM filled.players; INSERT INTO server_seeds SELECT * FROM filled.server_seeds;
        INSERT INTO drops SELECT * FROM filled.drops; DETACH filled`)
      const { turns, result } = await turnsDuring(() => memory.listDrops(window))
      expect(result.map((d) => d.id)).toEqual(newestInWindow)
      expect(memory._reader).toBeNull()
      expect(turns).toBe(0)
    } finally {
      await memory.close()
    }
  })

  it.runIf(fs.existsSync('/proc/thread-self'))('runs below the writer\'s priority, the event loop\'s unchanged', async () => {
    const thisThread = Number(fs.readlinkSync('/proc/thread-self').split('/').pop())
    await store.listDrops({ room: '16-medium.3', limit: 1 })
    const now = threadNices()
    expect(READER_THREAD_NICE).toBeGreaterThan(WRITER_THREAD_NICE)
    expect([...now.values()].filter((nice) => nice === READER_THREAD_NICE)).toHaveLength(1)
    expect(now.get(thisThread)).not.toBe(READER_THREAD_NICE)
  })

  it('refuses what is not one of its reads, and settles what a dead thread held, then starts a new one', async () => {
    await expect(store._reader.run('commitBatch', {})).rejects.toThrow(/no read commitBatch/)
    await store.listDrops({ room: '16-medium.3', limit: 1 })
    const first = store._reader.worker
    const pending = store.listDrops(window)
    await first.terminate()
    // Killed before or after it answered: the promise settles either way, never hangs.
    const outcome = await pending.then((drops) => drops.length, (error) => error.message)
    if (typeof outcome === 'number') expect(outcome).toBe(100)
    else expect(outcome).toMatch(/SQLite reader thread exited/)
    expect((await store.listDrops({ room: '16-medium.3', limit: 2 })).map((d) => d.id)).toEqual([59_903, 59_803])
    expect(store._reader.worker).not.toBe(first)
  })

  it('refuses a read once its store is closed, without starting a thread: an export cut short by a shutdown ends with an error', async () => {
    const second = new SqliteStore({ file })
    const pages = second.iterateDrops({ from: 1, to: 5_000 }, 1000)
    expect((await pages.next()).value.id).toBe(1)
    for (let i = 2; i <= 1000; i++) await pages.next()
    await second.close()
    await expect(pages.next()).rejects.toMatchObject({ code: 'SQLITE_CLOSED', message: expect.stringMatching(/reader thread is closed/) })
    expect(second._reader.worker).toBeNull()
    await expect(second.listDrops({ limit: 1 })).rejects.toMatchObject({ code: 'SQLITE_CLOSED' })
    expect(second._reader.worker).toBeNull()
  })

  it('a read-only connection, as the thread opens (sqlite-database.js readOnly), cannot write', () => {
    const db = openSqliteDatabase(file, { readOnly: true })
    try {
      expect(() => db.exec("UPDATE players SET balance = 1 WHERE id = 'p'")).toThrow(/readonly/)
    } finally {
      db.close()
    }
  })
})
