import fs from 'node:fs'
import path from 'node:path'

/** Bytes the reserve file holds: room for a start-up (WAL, its index) and a recovery's settlements. */
export const DISK_RESERVE_BYTES = 1024 * 1024

/** After a release, the reserve is made again no sooner than this, and only with twice its size free. */
const RESTORE_EVERY_MS = 5000

/**
 * A preallocated file beside the SQLite ledger that gives its space back
 * when the disk is full. A disk filled by something else (logs, a backup)
 * leaves the ledger no room to commit, and a process started on it no room
 * for its WAL: the start fails with "database or disk is full" even once the
 * filler shrank, if the WAL takes what came back. So the reserve is let go
 * as soon as a write fails for want of space (the retried settlements then
 * get it), and at start when the disk has less than the reserve free (the
 * start and its recovery get it); it is made again, in the background of
 * later writes, once twice its size is free.
 */
export class DiskReserve {
  /** @param {string} file @param {{ bytes?: number, now?: () => number }} [options] */
  constructor (file, { bytes = DISK_RESERVE_BYTES, now = Date.now } = {}) {
    this.file = file
    this.bytes = bytes
    this.now = now
    this._lastTry = -Infinity
    /** @type {Promise<void> | null} a restore being written */
    this._restoring = null
  }

  /** Whether the reserve file is there, whole. */
  get held () {
    try {
      return fs.statSync(this.file).size >= this.bytes
    } catch {
      return false
    }
  }

  /** Frees the reserve's space (a write failed with SQLITE_FULL). @returns {boolean} it was held */
  release () {
    this._lastTry = this.now()
    try {
      fs.unlinkSync(this.file)
      return true
    } catch {
      return false
    }
  }

  /** At start: frees the reserve if the disk has less than its size free. @returns {boolean} released */
  releaseIfLow () {
    if (!this.held || freeBytes(this.file) >= this.bytes) return false
    return this.release()
  }

  /**
   * After a write that succeeded: makes the reserve (again) if it is missing
   * and the disk has room, in the background (a 1 MiB write and its fsync
   * never hold the event loop).
   */
  restore () {
    if (this._restoring || this.now() - this._lastTry < RESTORE_EVERY_MS) return
    this._lastTry = this.now()
    if (this.held || freeBytes(this.file) < 2 * this.bytes) return
    this._restoring = this._write().finally(() => { this._restoring = null })
  }

  /** Waits for a restore in progress (the store's close: nothing of the ledger's stays open after it). */
  async idle () {
    await this._restoring
  }

  async _write () {
    const temp = `${this.file}.new`
    try {
      const handle = await fs.promises.open(temp, 'w')
      try {
        // Written, not sparse: the blocks must really be taken to be given back later.
        await handle.writeFile(Buffer.alloc(this.bytes))
        await handle.sync()
      } finally {
        await handle.close()
      }
      await fs.promises.rename(temp, this.file)
    } catch {
      await fs.promises.rm(temp, { force: true })
    }
  }
}

/** Bytes free for this process on the filesystem holding `file`. */
function freeBytes (file) {
  try {
    const stats = fs.statfsSync(path.dirname(file))
    return stats.bavail * stats.bsize
  } catch {
    return Infinity
  }
}

/**
 * At start, before anything else writes: a WAL left by a process that was
 * killed is copied into the database and truncated, so that it does not hold
 * the disk's space while the start and its recovery need it. A failure is
 * left to the first write to report.
 * @param {{ exec: (sql: string) => unknown }} db
 */
export function checkpointLeftoverWal (db) {
  try {
    db.exec('PRAGMA wal_checkpoint(TRUNCATE)')
  } catch {}
}
