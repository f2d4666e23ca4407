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
   * @param {{ commitBatch: (batch: import('../store/records.js').LedgerBatch) => Promise<void> }} options.store
   * @param {(batch: PendingBatch, outcome?: any) => void} options.onCommitted outcome: what the store's commitBatch returned
   * @param {(batch: PendingBatch, error: unknown) => void} options.onFailed
   * @param {import('../metrics.js').Metrics} [options.metrics]
   * @param {{ error: Function }} [options.log]
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

  /** @param {import('../arena.js').Drop} drop */
  addDrop (drop) {
    this.open.drops.push(drop)
  }

  /** @param {Settlement} settlement */
  addSettlement (settlement) {
    this.open.settlements.push(settlement)
  }

  /**
   * Takes back the drops of the open batch (not yet sent to the store) that
   * match `predicate`: they will never be written.
   * @param {(drop: import('../arena.js').Drop) => boolean} predicate
   * @returns {import('../arena.js').Drop[]}
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
      // The shared ledger (clustered) returns what it refused and the committed balances.
      outcome = await this.store.commitBatch(toLedgerBatch(batch))
    } catch (error) {
      this.metrics?.commitFailures.inc()
      this._callback(this.onFailed, batch, error)
      return
    }
    this.metrics?.commitDuration.observe(Number(process.hrtime.bigint() - started) / 1e9)
    this._callback(this.onCommitted, batch, outcome ?? undefined)
  }

  _callback (callback, batch, error) {
    try {
      callback(batch, error)
    } catch (callbackError) {
      // The transaction's outcome stands; a failing announcement must not undo or repeat it.
      this.log?.error({ err: callbackError }, 'ledger callback failed')
    }
  }
}

/**
 * @typedef {object} Settlement a landed ball waiting to be written
 * @property {import('../arena.js').Drop} drop
 * @property {number} bucket @property {number} multiplier @property {number} payout
 * @property {number} ticks @property {string} stateHash
 * @property {number} tick room tick at landing (drop.startTick + ticks)
 * @property {number} settledAt ms @property {number} attempts commits tried so far
 */

/** @typedef {{ drops: import('../arena.js').Drop[], settlements: Settlement[] }} PendingBatch */

function newBatch () {
  return { drops: [], settlements: [] }
}

function noop () {}

/**
 * The rows one batch writes: new drops, settlements, one net balance change
 * per player, the highest nonce used per seed, and client seeds changed by
 * `drop {clientSeed}`.
 * @param {PendingBatch} batch
 * @returns {import('../store/records.js').LedgerBatch}
 */
export function toLedgerBatch ({ drops, settlements }) {
  const balances = new Map()
  const nonces = new Map()
  const clientSeeds = new Map()
  const newDrops = drops.map((drop) => {
    balances.set(drop.playerId, (balances.get(drop.playerId) ?? 0) - drop.bet)
    nonces.set(drop.seedId, Math.max(nonces.get(drop.seedId) ?? 0, drop.nonce + 1))
    if (drop.clientSeedChange) clientSeeds.set(drop.playerId, drop.clientSeed)
    return {
      id: drop.id,
      playerId: drop.playerId,
      room: drop.roomId,
      rows: drop.rows,
      risk: drop.risk,
      engineVersion: drop.engineVersion,
      serverSeedId: drop.seedId,
      serverSeedHash: drop.serverSeedHash,
      clientSeed: drop.clientSeed,
      nonce: drop.nonce,
      dropSeed: drop.dropSeed,
      bet: drop.bet,
      startTick: drop.startTick,
      createdAt: drop.createdAt
    }
  })
  const newSettlements = settlements.map((s) => {
    balances.set(s.drop.playerId, (balances.get(s.drop.playerId) ?? 0) + s.payout)
    return {
      id: s.drop.id,
      bucket: s.bucket,
      multiplier: s.multiplier,
      payout: s.payout,
      ticks: s.ticks,
      stateHash: s.stateHash,
      settledAt: s.settledAt
    }
  })
  return {
    drops: newDrops,
    settlements: newSettlements,
    balances: [...balances].filter(([, delta]) => delta !== 0).map(([playerId, delta]) => ({ playerId, delta })),
    nonces: [...nonces].map(([seedId, nextNonce]) => ({ seedId, nextNonce })),
    clientSeeds: [...clientSeeds].map(([playerId, clientSeed]) => ({ playerId, clientSeed }))
  }
}
