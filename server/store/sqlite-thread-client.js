import { Worker } from 'node:worker_threads'

/**
 * The store's client of one of its SQLite threads (the writer:
 * sqlite-writer-thread.js; the reader: sqlite-reader-thread.js): each
 * runs on a worker thread with its own connection, started on the first
 * call, and answers each `{ id, op, args }` with `{ id, result }` or
 * `{ id, error, code }` (the error's message and SQLite's code, e.g.
 * SQLITE_BUSY), in the order the calls were sent. A thread that dies
 * fails every call it held (a write it held was rolled back with its
 * connection) and the next call starts a new one. Once closed, a call is
 * refused (code SQLITE_CLOSED) rather than starting a thread that would
 * keep the process alive after its store closed (an export's next page
 * after shutdown).
 */
export class SqliteThreadClient {
  /**
   * @param {{ entry: URL, dataKey: string, name: string }} thread the thread's module (WRITER_THREAD,
   *   READER_THREAD), the key of its workerData that tells the module it was started as that
   *   thread, and its name for errors
   * @param {object} data what the thread opens its connection with
   */
  constructor ({ entry, dataKey, name }, data) {
    this.entry = entry
    this.dataKey = dataKey
    this.data = data
    this.name = name
    /** @type {Worker | null} */
    this.worker = null
    this.nextId = 1
    /** @type {Map<number, { resolve: (result: any) => void, reject: (error: Error) => void }>} */
    this.pending = new Map()
    /** settles when the last call sent has */
    this._last = Promise.resolve()
    this.closed = false
  }

  /**
   * @param {string} op @param {any} [args]
   * @returns {Promise<any>} the thread's result (a write's: once durable)
   */
  run (op, args) {
    if (this.closed) return Promise.reject(Object.assign(new Error(`the SQLite ${this.name} thread is closed: its store was closed`), { code: 'SQLITE_CLOSED' }))
    const worker = this.worker ?? this._start()
    const id = this.nextId++
    const answered = new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject })
      worker.postMessage({ id, op, args })
    })
    this._last = answered.catch(() => {})
    return answered
  }

  _start () {
    const worker = new Worker(this.entry, { workerData: { [this.dataKey]: this.data } })
    worker.on('message', ({ id, result, error, code }) => {
      const waiter = this.pending.get(id)
      if (!waiter) return
      this.pending.delete(id)
      if (error === undefined) waiter.resolve(result)
      else waiter.reject(Object.assign(new Error(error), { code }))
    })
    const lost = (error) => {
      if (this.worker === worker) this.worker = null
      for (const waiter of this.pending.values()) waiter.reject(error)
      this.pending.clear()
    }
    worker.on('error', lost)
    worker.on('exit', (code) => lost(new Error(`the SQLite ${this.name} thread exited (${code})`)))
    this.worker = worker
    return worker
  }

  /** Stops the thread once the calls sent to it are answered; later calls are refused. */
  async close () {
    this.closed = true
    await this._last
    const worker = this.worker
    if (!worker) return
    this.worker = null
    const exited = new Promise((resolve) => worker.once('exit', resolve))
    worker.postMessage({ type: 'close' })
    await exited
  }
}
