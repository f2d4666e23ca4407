/**
 * The SQLite ledger's writer thread: the ledger's writes as transactions
 * (prepareWrites: the tick's batches, new players, seed rotations, and the
 * end of a checkpoint), and the
 * thread that runs them on a connection of its own (the store starts it:
 * SqliteStore in sqlite-store.js, through SqliteThreadClient). It runs the writes it is sent in order,
 * each durable (synchronous=FULL) before it answers with the write's
 * result; a write that fails answers with the error's message and SQLite
 * code (SQLITE_BUSY: the write lock stayed held by someone else for the
 * whole busy timeout).
 *
 * The thread runs at a lower priority than the event loop (its nice
 * value): on a busy core its bursts of page writes wait for
 * the tick instead of delaying it (see loadtest/RESULTS.md, "the writer
 * thread's priority"). Imported anywhere else (an in-memory store runs the
 * same transactions on its own connection), this file starts no thread.
 * Writes that wait while the thread is busy share a transaction, each in
 * a savepoint of its own (runWriterThread; prepareWrites' `together`).
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
  const countSettled = db.prepare(DROP_SQL.sqlite.countSettled)
  const credit = db.prepare('UPDATE players SET balance = balance + ? WHERE id = ?')
  const clientSeed = db.prepare('UPDATE players SET client_seed = ? WHERE id = ?')
  const balanceOf = db.prepare('SELECT balance FROM players WHERE id = ?')
  const insertPlayer = db.prepare('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES (?, ?, ?, ?, ?)')
  const insertSeed = db.prepare('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES (?, ?, ?, ?, 1, 0, ?)')
  // A retired seed keeps its final count: what its reveal says it was used for.
  const retireSeed = db.prepare(`UPDATE server_seeds AS s SET active = 0, revealed_at = ?, next_nonce = ${NEXT_NONCE_SQL.sqlite}
    WHERE s.id = ? AND s.player_id = ? AND s.active = 1`)

  /** Each write's statements, run inside a transaction its caller opened. */
  const work = {
    /**
     * The batch's rows; returns what it committed (one process owns a
     * SQLite ledger, so nothing is refused) and the touched players'
     * balances as committed.
     * @param {import('./records.js').LedgerBatch} batch
     * @returns {import('../game/money.js').CommitOutcome}
     */
    commitBatch: (batch) => {
      for (const d of batch.drops) insertDrop.run(...newDropValues(d))
      for (const s of batch.settlements) {
        if (settle.run(...settlementValues(s)).changes !== 1) throw new Error(`drop ${s.id} is not in flight; refusing to settle it twice`)
        countSettled.run(s.id)
      }
      for (const b of batch.balances) {
        if (credit.run(b.delta, b.playerId).changes !== 1) throw new Error(`no player ${b.playerId}`)
      }
      for (const c of batch.clientSeeds) clientSeed.run(c.clientSeed, c.playerId)
      const balances = new Map()
      for (const playerId of batch.players ?? []) balances.set(playerId, Number(balanceOf.get(playerId)?.balance))
      return wholeBatchCommitted(batch, balances)
    },
    createPlayer: ({ id, tokenHash, balance, clientSeed, createdAt, seed }) => {
      insertPlayer.run(id, tokenHash, balance, clientSeed, createdAt)
      insertSeed.run(seed.id, id, seed.seed, seed.hash, createdAt)
    },
    rotateSeed: ({ playerId, oldSeedId, newSeed, at }) => {
      if (retireSeed.run(at, oldSeedId, playerId).changes !== 1) throw new Error(`seed ${oldSeedId} is not the active seed of ${playerId}`)
      insertSeed.run(newSeed.id, playerId, newSeed.seed, newSeed.hash, at)
    }
  }

  return {
    /** The batch whole or not at all (work.commitBatch). */
    commitBatch: (batch) => immediateTransaction(db, () => work.commitBatch(batch)),
    createPlayer: (player) => immediateTransaction(db, () => work.createPlayer(player)),
    rotateSeed: (rotation) => immediateTransaction(db, () => work.rotateSeed(rotation)),
    /**
     * Copies what the checkpoint thread's last pass left in the WAL (the
     * frames committed while it ran): between two batches, with no write
     * beside it, so it copies all and the next commit starts the WAL over.
     */
    checkpoint: () => checkpointPassive(db),
    /**
     * Several writes (never `checkpoint`) in ONE transaction, and so one
     * fsync, each in a savepoint of its own: a write that throws is undone
     * alone and the others stand, as if each had had its transaction. What
     * breaks the transaction itself (SQLite rolled it back: a full disk, an
     * I/O error) or its commit fails every write of the group.
     * @param {{ op: string, args: any }[]} writes
     * @returns {({ result: any } | { error: Error })[]} in the writes' order, all durable
     */
    together: (writes) => groupTransaction(db, writes.map(({ op, args }) => () => work[op](args)))
  }
}

/**
 * Runs each of `jobs` in a savepoint of one immediateTransaction and
 * commits it; the outcomes once committed (an error each where the group
 * could not be: see prepareWrites' `together`).
 * @param {import('node:sqlite').DatabaseSync} db @param {(() => any)[]} jobs
 */
function groupTransaction (db, jobs) {
  try {
    return immediateTransaction(db, () => jobs.map((job) => inSavepoint(db, job)))
  } catch (error) {
    return jobs.map(() => ({ error }))
  }
}

/**
 * One job inside a transaction: undone alone if it throws, unless SQLite
 * rolled the whole transaction back (what ran before it is gone too: the
 * error goes up to fail the group).
 * @param {import('node:sqlite').DatabaseSync} db @param {() => any} job
 * @returns {{ result: any } | { error: Error }}
 */
function inSavepoint (db, job) {
  db.exec('SAVEPOINT write')
  try {
    const result = job()
    db.exec('RELEASE write')
    return { result }
  } catch (error) {
    if (!db.isTransaction) throw error
    db.exec('ROLLBACK TO write')
    db.exec('RELEASE write')
    return { error: withSqliteCode(error) }
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

/**
 * This file as a thread (SqliteThreadClient): its module, and the key of its
 * workerData that tells it it was started as the writer thread.
 */
export const WRITER_THREAD = Object.freeze({ entry: new URL(import.meta.url), dataKey: 'plinkoSqliteWriter', name: 'writer' })

/**
 * Writes the thread puts in one transaction at most: a burst of sign-ups
 * waiting behind a commit goes in a few transactions, not one each, and
 * none grows long enough to hold the next tick's commit for more than a
 * few milliseconds.
 */
export const MAX_WRITES_PER_TRANSACTION = 256

/**
 * The thread's entry: opens its connection and answers each `{ id, op,
 * args }` with `{ id, result }` or `{ id, error, code }`, until `{ type:
 * 'close' }`. Writes are run in the order they came; the ones that arrived
 * while the thread was busy (Node hands a port's waiting messages over in
 * one go) share a transaction (prepareWrites' `together`), so a commit's
 * fsync is paid once for all of them: one a sign-up at a time, 300
 * sign-ups a second took the whole writer and held every tick's commit
 * behind them for seconds (loadtest/RESULTS.md).
 * @param {{ file: string, busyTimeoutMs?: number, nice: number }} options
 */
function runWriterThread ({ file, busyTimeoutMs, nice }) {
  if (nice > 0) lowerThisThreadPriority(nice)
  // Its commits never checkpoint: the checkpoint thread does (sqlite-checkpoint-thread.js).
  const db = openSqliteDatabase(file, { busyTimeoutMs, autoCheckpoint: false })
  const writes = prepareWrites(db)
  /** @type {{ id: number, op: string, args: any }[]} */
  let waiting = []
  let scheduled = false
  const answer = (id, outcome) => {
    if ('error' in outcome) parentPort.postMessage({ id, error: outcome.error.message, code: outcome.error.code })
    else parentPort.postMessage({ id, result: outcome.result })
  }
  const runOne = ({ id, op, args }) => {
    try {
      if (!WRITES.includes(op)) throw new Error(`no write ${op}`)
      answer(id, { result: writes[op](args) })
    } catch (error) {
      answer(id, { error })
    }
  }
  const runWaiting = () => {
    scheduled = false
    const messages = waiting
    waiting = []
    for (const group of transactionGroups(messages)) {
      if (group.length === 1) {
        runOne(group[0])
        continue
      }
      const outcomes = writes.together(group)
      group.forEach((message, i) => answer(message.id, outcomes[i]))
    }
  }
  parentPort.on('message', (message) => {
    if (message.type === 'close') {
      runWaiting()
      db.close()
      parentPort.close()
      return
    }
    waiting.push(message)
    if (!scheduled) {
      scheduled = true
      setImmediate(runWaiting)
    }
  })
}

/** The writes that may share a transaction (`checkpoint` must run outside one). */
const GROUPED = new Set(WRITES.filter((op) => op !== 'checkpoint'))

/**
 * The waiting writes cut into transactions, in their order: runs of
 * writes that may share one (at most MAX_WRITES_PER_TRANSACTION each),
 * and every other write (`checkpoint`, an unknown one) alone.
 * @template {{ op: string }} M @param {M[]} messages @returns {M[][]}
 */
export function transactionGroups (messages) {
  const groups = []
  let open = null
  for (const message of messages) {
    if (!GROUPED.has(message.op)) {
      groups.push([message])
      open = null
    } else if (open && open.length < MAX_WRITES_PER_TRANSACTION) {
      open.push(message)
    } else {
      open = [message]
      groups.push(open)
    }
  }
  return groups
}

if (!isMainThread && workerData?.[WRITER_THREAD.dataKey]) runWriterThread(workerData[WRITER_THREAD.dataKey])
