/**
 * The SQLite ledger's checkpoint thread: copies the WAL's committed pages
 * into the database file on a connection of its own, every
 * CHECKPOINT_INTERVAL_MS, so that no commit waits for it. A checkpoint run
 * by a commit (SQLite's automatic one, which the writer's connection turns
 * off) holds that commit's answer until thousands of pages are copied and
 * fsynced: 20–70 ms about every hundredth tick, which is the p99 of the
 * commits and of every drop's acknowledgement behind them (see
 * loadtest/RESULTS.md, "the checkpoint off the commit's path"). WAL mode
 * lets a PASSIVE checkpoint run beside the writer: it copies what no reader
 * still needs and never blocks a write. But the WAL only starts over from
 * its first page when a write begins with every frame copied, and commits
 * keep coming while this thread copies: so after each pass the writer
 * thread copies what was committed since (the last few ticks' frames)
 * itself, between two batches (the `checkpoint` write, a few ms), and its
 * next commit starts the WAL over. The thread runs at the writer's lowered
 * priority (its nice value). SqliteCheckpointer (below) is the store's
 * handle on it; imported anywhere else, this file starts nothing.
 */
import { isMainThread, parentPort, workerData, Worker } from 'node:worker_threads'
import { openSqliteDatabase } from './sqlite-database.js'
import { lowerThisThreadPriority } from './thread-priority.js'

/**
 * How often (ms) the thread checkpoints. At the reference load a tick's
 * commit writes about 100 pages: 2 s is about 12,000, as many as the
 * automatic checkpoint it replaces let the WAL hold (a checkpoint copies a
 * page once however often it was rewritten since the last, so rarer
 * checkpoints copy fewer pages per drop).
 */
export const CHECKPOINT_INTERVAL_MS = 2000

/** The key of the thread's workerData (SqliteCheckpointer in sqlite-store.js sets it). */
export const CHECKPOINT_THREAD_DATA = 'plinkoSqliteCheckpointer'

/**
 * One PASSIVE checkpoint on `db`: SQLite's answer, as numbers.
 * @param {import('node:sqlite').DatabaseSync} db
 * @returns {{ busy: number, walPages: number, copiedPages: number }} busy 1: it could not
 *   finish (a reader or the writer held what it needed); walPages: frames in the WAL;
 *   copiedPages: frames now in the database (-1 each when the file is not in WAL mode)
 */
export function checkpointPassive (db) {
  const { busy, log, checkpointed } = db.prepare('PRAGMA wal_checkpoint(PASSIVE)').get()
  return { busy: Number(busy), walPages: Number(log), copiedPages: Number(checkpointed) }
}

/**
 * The store's handle on its checkpoint thread: started with the writer
 * (the first write), started again if it dies (the WAL would otherwise grow
 * without end), stopped by close(). After each pass it calls `finish` (the
 * store has the writer copy what was committed during the pass). nextCheckpoint() resolves
 * with the next pass's outcome (tests, and anyone who must know the
 * database file is up to date).
 */
export class SqliteCheckpointer {
  /**
   * @param {string} file the database file (not ':memory:')
   * @param {{ intervalMs?: number, nice?: number, busyTimeoutMs?: number, finish?: () => void }} [options]
   */
  constructor (file, { intervalMs = CHECKPOINT_INTERVAL_MS, nice = 0, busyTimeoutMs, finish = () => {} } = {}) {
    this.options = { file, intervalMs, nice, busyTimeoutMs }
    this.finish = finish
    /** @type {Worker | null} */
    this.worker = null
    this.closed = false
    /** @type {ReturnType<typeof checkpointPassive> | null} the last checkpoint's outcome */
    this.last = null
    /** @type {Error | null} the last checkpoint's failure, until one succeeds */
    this.failure = null
    /** @type {{ resolve: (outcome: any) => void, reject: (error: Error) => void }[]} */
    this._waiting = []
  }

  start () {
    if (this.worker || this.closed) return
    const worker = new Worker(new URL(import.meta.url), { workerData: { [CHECKPOINT_THREAD_DATA]: this.options } })
    worker.on('message', ({ checkpoint, error, code }) => {
      if (checkpoint) {
        this.last = checkpoint
        this.failure = null
        if (!this.closed) this.finish()
      } else {
        this.failure = Object.assign(new Error(`the SQLite checkpoint failed: ${error}`), { code })
      }
      for (const waiter of this._waiting.splice(0)) checkpoint ? waiter.resolve(checkpoint) : waiter.reject(this.failure)
    })
    worker.on('error', (error) => { this.failure = error })
    worker.on('exit', () => {
      if (this.worker === worker) this.worker = null
      // Died, not closed: a new one an interval later (one that cannot even open the file
      // must not be restarted in a loop), so the WAL keeps being copied.
      if (!this.closed) setTimeout(() => this.start(), this.options.intervalMs).unref()
    })
    worker.unref()
    this.worker = worker
  }

  /** @returns {Promise<ReturnType<typeof checkpointPassive>>} the next checkpoint's outcome */
  nextCheckpoint () {
    this.start()
    return new Promise((resolve, reject) => this._waiting.push({ resolve, reject }))
  }

  /** A pass now, beside the writer, as the interval would run one. @returns {Promise<ReturnType<typeof checkpointPassive>>} */
  checkpointNow () {
    const outcome = this.nextCheckpoint()
    this.worker.postMessage({ type: 'checkpoint' })
    return outcome
  }

  async close () {
    this.closed = true
    const worker = this.worker
    for (const waiter of this._waiting.splice(0)) waiter.reject(new Error('the SQLite checkpoint thread was stopped'))
    if (!worker) return
    this.worker = null
    const exited = new Promise((resolve) => worker.once('exit', resolve))
    // Held until it has exited: unreferenced, it would let the process end with close() unsettled.
    worker.ref()
    worker.postMessage({ type: 'close' })
    await exited
  }
}

/**
 * The thread's entry: a checkpoint every `intervalMs` and whenever it is
 * sent `{ type: 'checkpoint' }`, each answered to the parent as
 * `{ checkpoint }` or `{ error, code }`, until `{ type: 'close' }`.
 * @param {{ file: string, intervalMs: number, nice: number, busyTimeoutMs?: number }} options
 */
function runCheckpointThread ({ file, intervalMs, nice, busyTimeoutMs }) {
  if (nice > 0) lowerThisThreadPriority(nice)
  const db = openSqliteDatabase(file, { busyTimeoutMs })
  const pass = () => {
    try {
      parentPort.postMessage({ checkpoint: checkpointPassive(db) })
    } catch (error) {
      // A full disk, an I/O error: said, and tried again at the next interval.
      parentPort.postMessage({ error: error.message, code: error.code })
    }
  }
  const timer = setInterval(pass, intervalMs)
  parentPort.on('message', (message) => {
    if (message.type === 'checkpoint') pass()
    if (message.type !== 'close') return
    clearInterval(timer)
    db.close()
    parentPort.close()
  })
}

if (!isMainThread && workerData?.[CHECKPOINT_THREAD_DATA]) runCheckpointThread(workerData[CHECKPOINT_THREAD_DATA])
