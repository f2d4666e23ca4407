import { Worker } from 'node:worker_threads'

/**
 * Commits ledger batches on a worker thread with its own SQLite connection,
 * so the event loop never waits for a commit's fsync (it did: up to ~10 ms
 * per tick under load, see loadtest/RESULTS.md). Batches arrive one at a
 * time (the group commit waits for each), and a batch's promise settles only
 * once its transaction is durable, or rolled back with the error. Other
 * writes (sessions, seed rotation) stay on the store's own connection; SQLite
 * serializes the two writers (WAL, busy timeout).
 */
export class SqliteWriter {
  /** @param {string} file the database file (not ':memory:') */
  constructor (file) {
    this.file = file
    /** @type {Worker | null} */
    this.worker = null
    this.nextId = 1
    /** @type {Map<number, { resolve: () => void, reject: (error: Error) => void }>} */
    this.pending = new Map()
    /** settles when the last batch sent has */
    this._last = Promise.resolve()
  }

  /** @param {import('./records.js').LedgerBatch} batch */
  commit (batch) {
    const worker = this.worker ?? this._start()
    const id = this.nextId++
    const committed = new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject })
      worker.postMessage({ id, batch })
    })
    this._last = committed.catch(() => {})
    return committed
  }

  _start () {
    const worker = new Worker(new URL('./sqlite-writer-thread.js', import.meta.url), { workerData: { file: this.file } })
    worker.on('message', ({ id, error }) => {
      const waiter = this.pending.get(id)
      if (!waiter) return
      this.pending.delete(id)
      if (error === undefined) waiter.resolve()
      else waiter.reject(new Error(error))
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

  /** Stops the thread once the batches sent to it are done. */
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
