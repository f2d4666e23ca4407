/**
 * The SQLite ledger's writer thread (see sqlite-writer.js): its own
 * connection to the database file, running the writes it is sent one at a
 * time, each durable (synchronous=FULL) before it answers
 * with the write's result. A write that
 * fails answers with the error's message and SQLite code (SQLITE_BUSY: the
 * write lock stayed held by someone else for the whole busy timeout).
 *
 * It runs at a lower priority than the event loop (workerData.nice): on a
 * busy core its bursts of page writes and checkpoints wait for the tick
 * instead of delaying it (see loadtest/RESULTS.md, "the writer thread's
 * priority").
 */
import { parentPort, workerData } from 'node:worker_threads'
import { openSqliteDatabase } from './sqlite-database.js'
import { prepareWrites, WRITES } from './sqlite-writes.js'
import { lowerThisThreadPriority } from './thread-priority.js'

if (workerData.nice > 0) lowerThisThreadPriority(workerData.nice)

const db = openSqliteDatabase(workerData.file, { busyTimeoutMs: workerData.busyTimeoutMs })
const writes = prepareWrites(db)

parentPort.on('message', (message) => {
  if (message.type === 'close') {
    db.close()
    parentPort.close()
    return
  }
  try {
    if (!WRITES.includes(message.op)) throw new Error(`no write ${message.op}`)
    const result = writes[message.op](message.args)
    parentPort.postMessage({ id: message.id, result })
  } catch (error) {
    parentPort.postMessage({ id: message.id, error: error.message, code: error.code })
  }
})
