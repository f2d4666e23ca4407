import fs from 'node:fs'
import path from 'node:path'
import { DatabaseSync } from 'node:sqlite'

/**
 * Pages the WAL may hold before a commit on a connection that checkpoints
 * by itself copies them into the database (SQLite's automatic checkpoint;
 * its default is 1,000): the store's own connection (migrations, and every
 * write of an in-memory ledger). The writer thread's connection does not
 * checkpoint at all: the checkpoint thread does, beside it
 * (sqlite-checkpoint-thread.js), so that no commit waits for one.
 */
export const WAL_AUTOCHECKPOINT_PAGES = 10_000

/**
 * A connection to the ledger's SQLite file as every part of the store opens
 * it, on Node's own SQLite (`node:sqlite`, no native addon): WAL journal
 * with synchronous=FULL (a committed transaction survives a power cut),
 * foreign keys on, a 16 MB page cache, a checkpoint every
 * WAL_AUTOCHECKPOINT_PAGES (or none, for the writer thread), and a busy
 * timeout, since the store's connection (reads, migrations) and its writer
 * thread's take turns.
 * @param {string} file path or ':memory:'
 * @param {{ busyTimeoutMs?: number, autoCheckpoint?: boolean, readOnly?: boolean }} [options] busyTimeoutMs: how long a
 *   write waits for another connection's lock (default 5 s); autoCheckpoint false: this
 *   connection's commits never checkpoint (the checkpoint thread does); readOnly: a connection
 *   that only reads a ledger the store has opened (the reader thread's), its journal already WAL
 * @returns {DatabaseSync}
 */
export function openSqliteDatabase (file, { busyTimeoutMs = 5000, autoCheckpoint = true, readOnly = false } = {}) {
  if (file !== ':memory:') {
    try {
      fs.mkdirSync(path.dirname(file), { recursive: true })
    } catch (error) {
      throw new Error(`cannot create the SQLite ledger's directory ${path.dirname(file)}: ${error.message}`, { cause: error })
    }
  }
  let db
  try {
    db = new DatabaseSync(file, { timeout: Math.trunc(busyTimeoutMs), enableForeignKeyConstraints: true, readOnly })
    if (!readOnly) {
      db.exec('PRAGMA journal_mode = WAL')
      db.exec('PRAGMA synchronous = FULL')
    }
    // Node's SQLite is built with a 2 MB page cache; the ledger's indexes
    // (drops by player, time, room) outgrow it within minutes of play, and
    // every commit then re-reads their pages: 16 MB per connection, as
    // better-sqlite3 had (see docs/troubleshooting.md, the driver figures).
    db.exec('PRAGMA cache_size = -16000')
    if (!readOnly) db.exec(`PRAGMA wal_autocheckpoint = ${autoCheckpoint ? WAL_AUTOCHECKPOINT_PAGES : 0}`)
  } catch (error) {
    db?.close()
    throw cannotOpen(file, withSqliteCode(error))
  }
  return db
}

/** Why a ledger did not open, with the path and what SQLite needs there. */
function cannotOpen (file, error) {
  const wanted = file === ':memory:' ? '' : `; SQLite must be able to write ${file} and create files in ${path.dirname(file)} (the WAL journal keeps ${path.basename(file)}-wal and -shm beside it)`
  return Object.assign(new Error(`cannot open the SQLite ledger ${file}: ${error.message}${wanted}`, { cause: error }), { code: error.code })
}

/** SQLite's primary result codes the store tells apart (https://sqlite.org/rescode.html). */
const RESULT_CODES = new Map([[5, 'SQLITE_BUSY'], [6, 'SQLITE_LOCKED'], [8, 'SQLITE_READONLY'], [13, 'SQLITE_FULL'], [14, 'SQLITE_CANTOPEN'], [19, 'SQLITE_CONSTRAINT']])

/** The error, its `code` set to SQLite's name for its result code where it has one of RESULT_CODES. */
export function withSqliteCode (error) {
  const name = typeof error?.errcode === 'number' ? RESULT_CODES.get(error.errcode & 0xff) : undefined
  if (name) error.code = name
  return error
}
