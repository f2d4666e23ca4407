import fs from 'node:fs'
import path from 'node:path'
import Database from 'better-sqlite3'

/**
 * A connection to the ledger's SQLite file as every part of the store opens
 * it: WAL journal with synchronous=FULL (a committed transaction survives a
 * power cut), foreign keys on, and a busy timeout, since the store's
 * connection and its writer thread's take turns writing.
 * @param {string} file path or ':memory:'
 */
export function openSqliteDatabase (file) {
  if (file !== ':memory:') fs.mkdirSync(path.dirname(file), { recursive: true })
  const db = new Database(file)
  db.pragma('journal_mode = WAL')
  db.pragma('synchronous = FULL')
  db.pragma('foreign_keys = ON')
  db.pragma('busy_timeout = 5000')
  return db
}
