/**
 * The SQLite ledger's writer thread: the ledger's writes as transactions
 * (prepareWrites: the tick's batches, new players, seed rotations, and the
 * end of a checkpoint), and the
 * thread that runs them on a connection of its own (the store starts it:
 * SqliteWriter in sqlite-store.js). It runs the writes it is sent one at a
 * time, each durable (synchronous=FULL) before it answers with the write's
 * result; a write that fails answers with the error's message and SQLite
 * code (SQLITE_BUSY: the write lock stayed held by someone else for the
 * whole busy timeout).
 *
 * The thread runs at a lower priority than the event loop (its nice
 * value): on a busy core its bursts of page writes wait for
 * the tick instead of delaying it (see loadtest/RESULTS.md, "the writer
 * thread's priority"). Imported anywhere else (an in-memory store runs the
 * same transactions on its own connection), this file starts no thread.
 */
import { isMainThread, parentPort, workerData } from 'node:worker_threads'
import { wholeBatchCommitted, DROP_SQL, NEXT_NONCE_SQL, newDropValues, settlementValues } from './records.js'
import { openSqliteDatabase, withSqliteCode } from './sqlite-database.js'
import { lowerThisThreadPriority } from './thread-priority.js'
import { checkpointPassive } from './sqlite-checkpoint-thread.js'

/**
 * Every write of the SQLite ledger, as transactions prepared on one
 * connection: the tick's batch (new drops, settlements, credits, client
 * seeds), a new player with its first server seed, and a seed
 * rotation. Each takes the write lock up front (BEGIN IMMEDIATE) and is
 * committed whole or rolled back. The store runs them on this thread (below),
 * so no write, and no wait for another process's write lock, ever holds the
 * event loop; an in-memory database, which has no second connection, runs
 * them on its own.
 * @param {import('node:sqlite').DatabaseSync} db
 */
export function prepareWrites (db) {
  const insertDrop = db.prepare(DROP_SQL.sqlite.insert)
  const settle = db.prepare(DROP_SQL.sqlite.settle)
  const credit = db.prepare('UPDATE players SET balance = balance + ? WHERE id = ?')
  const clientSeed = db.prepare('UPDATE players SET client_seed = ? WHERE id = ?')
  const balanceOf = db.prepare('SELECT balance FROM players WHERE id = ?')
  const insertPlayer = db.prepare('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES (?, ?, ?, ?, ?)')
  const insertSeed = db.prepare('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES (?, ?, ?, ?, 1, 0, ?)')
  // A retired seed keeps its final count: what its reveal says it was used for.
  const retireSeed = db.prepare(`UPDATE server_seeds AS s SET active = 0, revealed_at = ?, next_nonce = ${NEXT_NONCE_SQL.sqlite}
    WHERE s.id = ? AND s.player_id = ? AND s.active = 1`)

  return {
    /**
     * Writes the batch whole or not at all; returns what it committed (one
     * process owns a SQLite ledger, so nothing is refused) and the touched
     * players' balances as committed.
     * @param {import('./records.js').LedgerBatch} batch
     * @returns {import('../game/money.js').CommitOutcome}
     */
    commitBatch: (batch) => immediateTransaction(db, () => {
      for (const d of batch.drops) insertDrop.run(...newDropValues(d))
      for (const s of batch.settlements) {
        if (settle.run(...settlementValues(s)).changes !== 1) throw new Error(`drop ${s.id} is not in flight; refusing to settle it twice`)
      }
      for (const b of batch.balances) {
        if (credit.run(b.delta, b.playerId).changes !== 1) throw new Error(`no player ${b.playerId}`)
      }
      for (const c of batch.clientSeeds) clientSeed.run(c.clientSeed, c.playerId)
      const balances = new Map()
      for (const playerId of batch.players ?? []) balances.set(playerId, Number(balanceOf.get(playerId)?.balance))
      return wholeBatchCommitted(batch, balances)
    }),
    createPlayer: ({ id, tokenHash, balance, clientSeed, createdAt, seed }) => immediateTransaction(db, () => {
      insertPlayer.run(id, tokenHash, balance, clientSeed, createdAt)
      insertSeed.run(seed.id, id, seed.seed, seed.hash, createdAt)
    }),
    rotateSeed: ({ playerId, oldSeedId, newSeed, at }) => immediateTransaction(db, () => {
      if (retireSeed.run(at, oldSeedId, playerId).changes !== 1) throw new Error(`seed ${oldSeedId} is not the active seed of ${playerId}`)
      insertSeed.run(newSeed.id, playerId, newSeed.seed, newSeed.hash, at)
    }),
    /**
     * Copies what the checkpoint thread's last pass left in the WAL (the
     * frames committed while it ran): between two batches, with no write
     * beside it, so it copies all and the next commit starts the WAL over.
     */
    checkpoint: () => checkpointPassive(db)
  }
}

/**
 * Runs `work` in one transaction that takes the write lock up front
 * (BEGIN IMMEDIATE: a busy database fails here, before anything is done)
 * and commits it, or rolls it back and rethrows if anything in it throws.
 * node:sqlite's errors carry SQLite's result code as a number (`errcode`);
 * the one rethrown also has its name as `code` (SQLITE_BUSY, ...).
 * @template T @param {import('node:sqlite').DatabaseSync} db @param {() => T} work @returns {T}
 */
export function immediateTransaction (db, work) {
  try {
    db.exec('BEGIN IMMEDIATE')
  } catch (error) {
    throw withSqliteCode(error)
  }
  try {
    const result = work()
    db.exec('COMMIT')
    return result
  } catch (error) {
    if (db.isTransaction) {
      try { db.exec('ROLLBACK') } catch {} // SQLite may have rolled back already; the first error is the one to report
    }
    throw withSqliteCode(error)
  }
}

/** The names of the writes prepareWrites() returns (what the writer thread accepts). */
export const WRITES = Object.freeze(['commitBatch', 'createPlayer', 'rotateSeed', 'checkpoint'])

/** The key of the thread's workerData (SqliteWriter in sqlite-store.js sets it): this file was started as the writer thread. */
export const WRITER_THREAD_DATA = 'plinkoSqliteWriter'

/**
 * The thread's entry: opens its connection and answers each `{ id, op,
 * args }` with `{ id, result }` or `{ id, error, code }`, until `{ type:
 * 'close' }`.
 * @param {{ file: string, busyTimeoutMs?: number, nice: number }} options
 */
function runWriterThread ({ file, busyTimeoutMs, nice }) {
  if (nice > 0) lowerThisThreadPriority(nice)
  // Its commits never checkpoint: the checkpoint thread does (sqlite-checkpoint-thread.js).
  const db = openSqliteDatabase(file, { busyTimeoutMs, autoCheckpoint: false })
  const writes = prepareWrites(db)
  parentPort.on('message', (message) => {
    if (message.type === 'close') {
      db.close()
      parentPort.close()
      return
    }
    try {
      if (!WRITES.includes(message.op)) throw new Error(`no write ${message.op}`)
      parentPort.postMessage({ id: message.id, result: writes[message.op](message.args) })
    } catch (error) {
      parentPort.postMessage({ id: message.id, error: error.message, code: error.code })
    }
  })
}

if (!isMainThread && workerData?.[WRITER_THREAD_DATA]) runWriterThread(workerData[WRITER_THREAD_DATA])
