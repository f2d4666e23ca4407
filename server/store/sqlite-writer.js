import { Worker } from 'node:worker_threads'

/**
 * The writer thread's nice value: below the event loop's 0, so that where
 * both want the same core the ticks go first (a commit waits a little; at
 * the most players one core holds, see loadtest/RESULTS.md). Not so low
 * that it starves: at 19 the commits fell behind and merged into batches
 * large enough to delay the acks (drop → dropped p99 0.55 s).
 */
export const WRITER_THREAD_NICE = 10

/**
 * Runs the ledger's writes (sqlite-writes.js: the tick's batches, new
 * players, seed rotations) on a worker thread with its own SQLite
 * connection, so the event loop never waits for a commit's fsync (it did: up
 * to ~10 ms per tick under load, see loadtest/RESULTS.md) nor for a write
 * lock another process holds (a session once froze every room for the 5 s
 * busy timeout). Writes run one at a time in the order they are sent, and
 * each promise settles only once its transaction is durable, or rolled back
 * with the error (its `code` is SQLite's, e.g. SQLITE_BUSY). The thread
 * runs at WRITER_THREAD_NICE.
 */
export class SqliteWriter {
  /** @param {string} file the database file (not ':memory:') @param {{ busyTimeoutMs?: number }} [options] */
  constructor (file, { busyTimeoutMs } = {}) {
    this.file = file
    this.busyTimeoutMs = busyTimeoutMs
    /** @type {Worker | null} */
    this.worker = null
    this.nextId = 1
    /** @type {Map<number, { resolve: (result: any) => void, reject: (error: Error) => void }>} */
    this.pending = new Map()
    /** settles when the last batch sent has */
    this._last = Promise.resolve()
  }

  /**
   * @param {import('./sqlite-writes.js').WRITES[number]} op @param {any} args
   * @returns {Promise<any>} the write's result, once durable
   */
  run (op, args) {
    const worker = this.worker ?? this._start()
    const id = this.nextId++
    const committed = new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject })
      worker.postMessage({ id, op, args })
    })
    this._last = committed.catch(() => {})
    return committed
  }

  _start () {
    const worker = new Worker(new URL('./sqlite-writer-thread.js', import.meta.url), { workerData: { file: this.file, busyTimeoutMs: this.busyTimeoutMs, nice: WRITER_THREAD_NICE } })
    worker.on('message', ({ id, result, error, code }) => {
      const waiter = this.pending.get(id)
      if (!waiter) return
      this.pending.delete(id)
      if (error === undefined) waiter.resolve(result)
      else waiter.reject(Object.assign(new Error(error), { code }))
    })
    // A thread that dies takes its open transaction with it (rolled back): fail what waited, start afresh next time.
    const lost = (error) => {
      if (this.worker === worker) this.worker = null
      for (const waiter of this.pending.values()) waiter.reject(error)
      this.pending.clear()
    }
    worker.on('error', lost)
    worker.on('exit', (code) => lost(new Error(`the SQLite writer thread exited (${code})`)))
    this.worker = worker
    return worker
  }

  /** Stops the thread once the writes sent to it are done. */
  async close () {
    await this._last
    const worker = this.worker
    if (!worker) return
    this.worker = null
    const exited = new Promise((resolve) => worker.once('exit', resolve))
    worker.postMessage({ type: 'close' })
    await exited
  }
}
