import { toLedgerBatch } from './ledger-batch.js'

/**
 * Group commit: everything one tick changes (drops accepted, balls landed)
 * is written in ONE transaction, and transactions run strictly one after
 * another in the order their ticks happened. Nothing is announced until its
 * transaction has committed: `onCommitted` runs only then, `onFailed` after
 * a rollback. Other ledger writes (seed rotation, client seed) join the same
 * queue through `run()`, so they are ordered with the drops around them.
 *
 * When the database is slower than the clock (a commit still running when
 * the next tick ends), the ticks that end meanwhile are merged into the
 * next transaction instead of queueing one transaction per tick: the queue
 * never grows, and a tick is still never split across transactions.
 */
export class GroupCommit {
  /**
   * @param {object} options
   * @param {{ commitBatch: (batch: import('../store/records.js').LedgerBatch) => Promise<import('./money.js').CommitOutcome> }} options.store
   * @param {(batch: PendingBatch, outcome: import('./money.js').CommitOutcome) => void} options.onCommitted outcome: what the store's commitBatch returned
   * @param {(batch: PendingBatch, error: unknown) => void} options.onFailed
   * @param {import('../metrics.js').Metrics} options.metrics
   * @param {{ error: Function }} options.log
   */
  constructor ({ store, onCommitted, onFailed, metrics, log }) {
    this.store = store
    this.onCommitted = onCommitted
    this.onFailed = onFailed
    this.metrics = metrics
    this.log = log
    this.open = newBatch()
    this.tail = Promise.resolve()
    this.queued = 0
    this._flushWanted = false
  }

  /** @param {import('./drop.js').Drop} drop */
  addDrop (drop) {
    this.open.drops.push(drop)
  }

  /** @param {import('./drop.js').Settlement} settlement */
  addSettlement (settlement) {
    this.open.settlements.push(settlement)
  }

  /**
   * Takes back the drops of the open batch (not yet sent to the store) that
   * match `predicate`: they will never be written.
   * @param {(drop: import('./drop.js').Drop) => boolean} predicate
   * @returns {import('./drop.js').Drop[]}
   */
  withdrawDrops (predicate) {
    const withdrawn = this.open.drops.filter(predicate)
    if (withdrawn.length > 0) this.open.drops = this.open.drops.filter((drop) => !predicate(drop))
    return withdrawn
  }

  /**
   * Ends a tick: seals the open batch and queues its transaction, or, while
   * an earlier one is still being written, keeps it open so the following
   * ticks join it. Called once per tick.
   */
  flush () {
    if (this.queued > 0) {
      this._flushWanted = true
      return
    }
    this._seal()
  }

  /**
   * Runs `job` after everything accepted so far has been written, and before
   * anything later. @template T @param {() => Promise<T>} job @returns {Promise<T>}
   */
  run (job) {
    this._seal()
    return this._enqueue(job)
  }

  /** Resolves when everything accepted so far has been written (or has failed). */
  async drain () {
    this._seal()
    while (this.queued > 0) await this.tail
  }

  _seal () {
    this._flushWanted = false
    const batch = this.open
    if (batch.drops.length === 0 && batch.settlements.length === 0) return
    this.open = newBatch()
    this._enqueue(() => this._commit(batch))
  }

  _enqueue (job) {
    this.queued++
    const result = this.tail.then(job).finally(() => {
      if (--this.queued === 0 && this._flushWanted) this._seal()
    })
    this.tail = result.then(noop, noop)
    return result
  }

  /** @param {PendingBatch} batch */
  async _commit (batch) {
    // A drop whose own batch failed was never recorded: drop its settlement.
    batch.settlements = batch.settlements.filter((s) => !s.drop.void)
    const started = process.hrtime.bigint()
    let outcome
    try {
      // What the ledger committed (a shared ledger may refuse drops) and the committed balances.
      outcome = await this.store.commitBatch(toLedgerBatch(batch))
    } catch (error) {
      this.metrics.commitFailures.inc()
      this._callback(this.onFailed, batch, error)
      return
    }
    this.metrics.commitDuration.observe(Number(process.hrtime.bigint() - started) / 1e9)
    this._callback(this.onCommitted, batch, outcome)
  }

  _callback (callback, batch, error) {
    try {
      callback(batch, error)
    } catch (callbackError) {
      // The transaction's outcome stands; a failing announcement must not undo or repeat it.
      this.log.error({ err: callbackError }, 'ledger callback failed')
    }
  }
}

/** @typedef {{ drops: import('./drop.js').Drop[], settlements: import('./drop.js').Settlement[] }} PendingBatch */

function newBatch () {
  return { drops: [], settlements: [] }
}

function noop () {}
