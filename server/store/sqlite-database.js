import fs from 'node:fs'
import path from 'node:path'
import Database from 'better-sqlite3'

/**
 * A connection to the ledger's SQLite file as every part of the store opens
 * it: WAL journal with synchronous=FULL (a committed transaction survives a
 * power cut), foreign keys on, and a busy timeout, since the store's
 * connection (reads, migrations) and its writer thread's take turns.
 * @param {string} file path or ':memory:'
 * @param {{ busyTimeoutMs?: number }} [options] how long a write waits for another connection's lock (default 5 s)
 */
export function openSqliteDatabase (file, { busyTimeoutMs = 5000 } = {}) {
  if (file !== ':memory:') fs.mkdirSync(path.dirname(file), { recursive: true })
  const db = new Database(file)
  db.pragma('journal_mode = WAL')
  db.pragma('synchronous = FULL')
  db.pragma('foreign_keys = ON')
  db.pragma(`busy_timeout = ${Math.trunc(busyTimeoutMs)}`)
  return db
}
