import { PAYOUT_RULE, balanceChanges } from './money.js'

/**
 * A drop's record, from acceptance to the ledger, in one place: its shape
 * in memory while it is in flight (Drop, Settlement), the rows a tick's
 * drops and landings are written as, and the group commit that writes each
 * tick's rows in one transaction, in tick order. (What players are told of
 * a drop is built in protocol/server-messages.js; what it costs and pays is
 * money.js.)
 */

// ---- the record ------------------------------------------------------------

/**
 * @typedef {object} Drop one bet on one ball, from acceptance to settlement
 * @property {number} id @property {import('./accounts.js').Account} account
 * @property {string} playerId @property {import('../rooms/room.js').Room} room
 * @property {string} roomId @property {number} rows @property {string} risk
 * @property {string} engineVersion @property {string} seedId @property {string} serverSeedHash
 * @property {string} clientSeed @property {number} nonce @property {string} dropSeed
 * @property {number} bet whole credits @property {number} payoutRule protocol/payout.js
 * @property {number} createdAt ms
 * @property {number} startTick @property {number} slot set by Room.release
 * @property {boolean} announced its row is committed and `dropped` was sent
 * @property {boolean} void its row could not be committed: ignored when it lands
 * @property {{ previous: string } | null} clientSeedChange the drop set a new client seed
 * @property {any} ref the client's ref, echoed to the connection that asked
 * @property {import('../realtime/connection.js').Connection | null} origin
 */

/**
 * @typedef {object} Settlement a landed ball waiting to be written
 * @property {Drop} drop
 * @property {number} bucket @property {number} multiplier @property {number} payout milli-credits
 * @property {number} ticks @property {string} stateHash
 * @property {number} tick room tick at landing (drop.startTick + ticks)
 * @property {number} settledAt ms @property {number} attempts commits tried so far
 */

/**
 * @param {object} facts
 * @param {number} facts.id @param {import('./accounts.js').Account} facts.account
 * @param {import('../rooms/room.js').Room} facts.room @param {number} facts.nonce
 * @param {string} facts.dropSeed @param {number} facts.bet
 * @param {{ previous: string } | null} facts.clientSeedChange
 * @param {any} facts.ref @param {any} facts.origin
 * @returns {Drop}
 */
export function createDrop ({ id, account, room, nonce, dropSeed, bet, clientSeedChange, ref, origin }) {
  return {
    id,
    account,
    playerId: account.playerId,
    room,
    roomId: room.id,
    rows: room.rows,
    risk: room.risk,
    engineVersion: room.board.engineVersion,
    seedId: account.seed.id,
    serverSeedHash: account.seed.hash,
    clientSeed: account.clientSeed,
    nonce,
    dropSeed,
    bet,
    payoutRule: PAYOUT_RULE,
    createdAt: Date.now(),
    startTick: 0,
    slot: -1,
    announced: false,
    void: false,
    clientSeedChange,
    ref,
    origin
  }
}

// ---- its rows --------------------------------------------------------------

/** @param {Drop} drop @returns {import('../store/records.js').NewDropRow} */
export function newDropRow (drop) {
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
    payoutRule: drop.payoutRule,
    startTick: drop.startTick,
    createdAt: drop.createdAt
  }
}

/** @param {Settlement} settlement @returns {import('../store/records.js').SettlementRow} */
export function settlementRow ({ drop, bucket, multiplier, payout, ticks, stateHash, settledAt }) {
  return { id: drop.id, bucket, multiplier, payout, ticks, stateHash, settledAt }
}

/**
 * The rows one batch writes: new drops (each its nonce's record:
 * records.js NEXT_NONCE_SQL), settlements, one net balance change per
 * player (money.js), client seeds changed by `drop {clientSeed}`, and every
 * player the batch touches (whose committed balances the store returns).
 * @param {{ drops: Drop[], settlements: Settlement[] }} batch
 * @returns {import('../store/records.js').LedgerBatch}
 */
export function toLedgerBatch ({ drops, settlements }) {
  const clientSeeds = new Map()
  for (const drop of drops) {
    if (drop.clientSeedChange) clientSeeds.set(drop.playerId, drop.clientSeed)
  }
  const changes = balanceChanges(drops, settlements)
  return {
    drops: drops.map(newDropRow),
    settlements: settlements.map(settlementRow),
    balances: [...changes].filter(([, delta]) => delta !== 0).map(([playerId, delta]) => ({ playerId, delta })),
    clientSeeds: [...clientSeeds].map(([playerId, clientSeed]) => ({ playerId, clientSeed })),
    players: [...changes.keys()]
  }
}

/** A batch that only sets a player's client seed (`POST /api/seeds/client`). @returns {import('../store/records.js').LedgerBatch} */
export function clientSeedBatch (playerId, clientSeed) {
  return { drops: [], settlements: [], balances: [], clientSeeds: [{ playerId, clientSeed }], players: [] }
}

// ---- the group commit -------------------------------------------------------

/**
 * Drops and settlements (entries) past which a batch kept open behind a slow
 * commit is sealed and queued: about four ticks at the reference load of
 * 6,000 players (50 drops and 50 landings a tick). Announcing a committed
 * batch costs about 15 µs of the event loop per drop and its landing, so
 * this keeps one batch's announcement near 6 ms, within a tick; the 750
 * drops a stall of the disk once merged into one batch held it 24 ms.
 */
export const MAX_MERGED_ENTRIES = 400

/**
 * Group commit: everything one tick changes (drops accepted, balls landed)
 * is written in ONE transaction, and transactions run strictly one after
 * another in the order their ticks happened. Nothing is announced until its
 * transaction has committed: `onCommitted` runs only then, `onFailed` after
 * a rollback. Other ledger writes (seed rotation, client seed) join the same
 * queue through `run()`, so they are ordered with the drops around them.
 *
 * A transaction gathers at least `ticksPerCommit` ticks (LEDGER_COMMIT_TICKS,
 * default 2): each commit costs the store a sync of its journal to the
 * disk and the writes of its hot pages whatever its size, so two ticks a
 * transaction took 2–4 points of a core off a process of 4,500 players
 * (loadtest/RESULTS.md), for up to a tick (17 ms) more before `dropped`.
 *
 * When the database is slower than the clock (a commit still running when
 * the next tick ends), the ticks that end meanwhile are merged into the
 * next transaction instead of queueing one transaction per tick, and a
 * tick is still never split across transactions. Merging stops at
 * MAX_MERGED_ENTRIES: after a long stall of the disk the ticks it held
 * queue as several transactions, so that announcing them (every reply and
 * room frame they held) is spread over several commits instead of holding
 * the event loop, and so the next ticks, in one go.
 */
export class GroupCommit {
  /**
   * @param {object} options
   * @param {{ commitBatch: (batch: import('../store/records.js').LedgerBatch) => Promise<import('./money.js').CommitOutcome> }} options.store
   * @param {(batch: PendingBatch, outcome: import('./money.js').CommitOutcome) => void} options.onCommitted outcome: what the store's commitBatch returned
   * @param {(batch: PendingBatch, error: unknown) => void} options.onFailed
   * @param {import('../metrics.js').Metrics} options.metrics
   * @param {{ error: Function }} options.log
   * @param {number} [options.maxMergedEntries] see MAX_MERGED_ENTRIES
   * @param {number} [options.ticksPerCommit] ticks a transaction gathers at least (1: every tick's own)
   */
  constructor ({ store, onCommitted, onFailed, metrics, log, maxMergedEntries = MAX_MERGED_ENTRIES, ticksPerCommit = 1 }) {
    this.store = store
    this.onCommitted = onCommitted
    this.onFailed = onFailed
    this.metrics = metrics
    this.log = log
    this.open = newBatch()
    this.tail = Promise.resolve()
    this.queued = 0
    this.maxMergedEntries = maxMergedEntries
    this.ticksPerCommit = ticksPerCommit
    /** ticks ended since the open batch was started */
    this._ticksOpen = 0
    this._flushWanted = false
  }

  /** @param {Drop} drop */
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
   * @param {(drop: Drop) => boolean} predicate
   * @returns {Drop[]}
   */
  withdrawDrops (predicate) {
    const withdrawn = this.open.drops.filter(predicate)
    if (withdrawn.length > 0) this.open.drops = this.open.drops.filter((drop) => !predicate(drop))
    return withdrawn
  }

  /**
   * Ends a tick: seals the open batch and queues its transaction, or keeps
   * it open so the following ticks join it, up to maxMergedEntries: until
   * it has gathered ticksPerCommit ticks, and while an earlier one is still
   * being written. Called once per tick (the clock never stops, so a batch
   * kept open is sealed at a later tick).
   */
  flush () {
    const open = this.open
    const entries = open.drops.length + open.settlements.length
    if (++this._ticksOpen < this.ticksPerCommit && entries < this.maxMergedEntries) return
    if (this.queued > 0 && entries < this.maxMergedEntries) {
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
    this._ticksOpen = 0
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

/** @typedef {{ drops: Drop[], settlements: Settlement[] }} PendingBatch */

function newBatch () {
  return { drops: [], settlements: [] }
}

function noop () {}
