import { createRequire } from 'node:module'
import path from 'node:path'

/**
 * better-sqlite3 behind the part of node:sqlite's `DatabaseSync` the
 * ledger uses (constructor options, exec, prepare, close, isOpen,
 * isTransaction; statements are better-sqlite3's own, whose run/get/all
 * take and return the same values), so that bench/sqlite-drivers.js runs the
 * very same store code on either driver. Loaded in place of `node:sqlite` by
 * bench/better-sqlite3-hooks.js, from the install named by
 * BETTER_SQLITE3_DIR (a prefix outside the project: nothing is added to it).
 */
const dir = process.env.BETTER_SQLITE3_DIR
if (!dir) throw new Error('BETTER_SQLITE3_DIR names no better-sqlite3 install (a prefix with node_modules/better-sqlite3)')
const Database = createRequire(path.join(path.resolve(dir), 'package.json'))('better-sqlite3')

/** better-sqlite3 names SQLite's result code (error.code); node:sqlite numbers it (error.errcode). */
const RESULT_CODES = { SQLITE_BUSY: 5, SQLITE_LOCKED: 6, SQLITE_READONLY: 8, SQLITE_FULL: 13, SQLITE_CANTOPEN: 14, SQLITE_CONSTRAINT: 19 }
const numbered = (error) => {
  const primary = typeof error?.code === 'string' ? /^SQLITE_[A-Z]+/.exec(error.code)?.[0] : undefined
  if (primary && RESULT_CODES[primary]) error.errcode = RESULT_CODES[primary]
  return error
}

export class DatabaseSync {
  constructor (file, { timeout, readOnly = false, enableForeignKeyConstraints = true } = {}) {
    try {
      this.db = new Database(file, { timeout, readonly: readOnly })
    } catch (error) {
      throw numbered(error)
    }
    if (enableForeignKeyConstraints) this.db.exec('PRAGMA foreign_keys = ON')
  }

  get isOpen () { return this.db.open }
  get isTransaction () { return this.db.inTransaction }

  exec (sql) {
    try {
      this.db.exec(sql)
    } catch (error) {
      throw numbered(error)
    }
  }

  prepare (sql) { return this.db.prepare(sql) }
  close () { this.db.close() }
}
