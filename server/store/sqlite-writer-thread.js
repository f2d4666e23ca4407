/**
 * The SQLite ledger's writer thread (see sqlite-writer.js): its own
 * connection to the database file, committing the batches it is sent one at
 * a time, each durable (synchronous=FULL) before it answers.
 */
import { parentPort, workerData } from 'node:worker_threads'
import { openSqliteDatabase } from './sqlite-database.js'
import { prepareBatchCommit } from './sqlite-batch.js'

const db = openSqliteDatabase(workerData.file)
const commit = prepareBatchCommit(db)

parentPort.on('message', (message) => {
  if (message.type === 'close') {
    db.close()
    parentPort.close()
    return
  }
  try {
    commit.immediate(message.batch)
    parentPort.postMessage({ id: message.id })
  } catch (error) {
    parentPort.postMessage({ id: message.id, error: error.message })
  }
})
