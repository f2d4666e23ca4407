/**
 * The SQLite ledger's writer thread (see sqlite-writer.js): its own
 * connection to the database file, running the writes it is sent one at a
 * time, each durable (synchronous=FULL) before it answers
 * with the write's result. A write that
 * fails answers with the error's message and SQLite code (SQLITE_BUSY: the
 * write lock stayed held by someone else for the whole busy timeout).
 */
import { parentPort, workerData } from 'node:worker_threads'
import { openSqliteDatabase } from './sqlite-database.js'
import { prepareWrites, WRITES } from './sqlite-writes.js'

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
    const result = writes[message.op].immediate(message.args)
    parentPort.postMessage({ id: message.id, result })
  } catch (error) {
    parentPort.postMessage({ id: message.id, error: error.message, code: error.code })
  }
})
