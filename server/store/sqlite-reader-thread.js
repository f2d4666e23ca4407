/**
 * The SQLite ledger's reader thread: the reads whose cost grows with what
 * they cover (an operator's listing of drops by time, room, player or
 * seed, an export's pages), run on a thread with a read-only connection
 * of its own, so that however many drops one reads, the event loop keeps
 * ticking the rooms (a page of a 100,000-drop time window held it for
 * 250–270 ms: bench/ledger-reads.js, loadtest/RESULTS.md). The store starts it (SqliteStore in
 * sqlite-store.js, through SqliteThreadClient); imported anywhere else
 * (an in-memory store runs the same reads on its own connection), this
 * file starts no thread. Point reads (an account, a drop by id, a room's
 * totals) stay on the store's connection: a few index pages, cheaper
 * than the hop to a thread.
 */
import { isMainThread, parentPort, workerData } from 'node:worker_threads'
import { dropsPage, driveDropsPage } from './drop-pages.js'
import { openSqliteDatabase, withSqliteCode } from './sqlite-database.js'
import { lowerThisThreadPriority } from './thread-priority.js'

/**
 * The reads of drops that may cover many of them, on one connection. Each
 * page's statements are prepared per call: their WHERE depends on the filter.
 * @param {import('node:sqlite').DatabaseSync} db
 */
export function prepareReads (db) {
  const selectDrops = (filter, order, limit) => driveDropsPage(dropsPage(filter, order, limit, 'sqlite'), (sql, params) => db.prepare(sql).all(...params))
  return {
    /** Newest first, at most `filter.limit`. @param {import('./drop-filter.js').DropFilter & { limit: number }} filter */
    listDrops: (filter) => selectDrops(filter, 'DESC', filter.limit),
    /**
     * An export's page: the next `pageSize` matches after the drop `afterId` (none: the first page).
     * @param {{ filter: import('./drop-filter.js').DropFilter, afterId?: number, pageSize: number }} page
     */
    dropsPage: ({ filter, afterId, pageSize }) => selectDrops({ ...filter, afterId }, 'ASC', pageSize)
  }
}

/** The names of the reads prepareReads() returns (what the reader thread accepts). */
export const READS = Object.freeze(['listDrops', 'dropsPage'])

/**
 * This file as a thread (SqliteThreadClient): its module, and the key of its
 * workerData that tells it it was started as the reader thread.
 */
export const READER_THREAD = Object.freeze({ entry: new URL(import.meta.url), dataKey: 'plinkoSqliteReader', name: 'reader' })

/**
 * The thread's entry: opens a read-only connection and answers each `{ id,
 * op, args }` with `{ id, result }` or `{ id, error, code }`, one at a
 * time in the order they came, until `{ type: 'close' }`.
 * @param {{ file: string, busyTimeoutMs?: number, nice: number }} options
 */
function runReaderThread ({ file, busyTimeoutMs, nice }) {
  if (nice > 0) lowerThisThreadPriority(nice)
  const db = openSqliteDatabase(file, { busyTimeoutMs, readOnly: true })
  const reads = prepareReads(db)
  parentPort.on('message', (message) => {
    if (message.type === 'close') {
      db.close()
      parentPort.close()
      return
    }
    const { id, op, args } = message
    try {
      if (!READS.includes(op)) throw new Error(`no read ${op}`)
      parentPort.postMessage({ id, result: reads[op](args) })
    } catch (error) {
      parentPort.postMessage({ id, error: error.message, code: withSqliteCode(error).code })
    }
  })
}

if (!isMainThread && workerData?.[READER_THREAD.dataKey]) runReaderThread(workerData[READER_THREAD.dataKey])
