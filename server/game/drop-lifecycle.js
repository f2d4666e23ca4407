import { deriveDropSeed, isValidClientSeed } from '../fairness/seeds.js'
import { gameError } from '../errors.js'
import { betCost, payoutFor, toCredits, RunningBalances } from './money.js'
import { createDrop, GroupCommit } from './drop.js'
import { droppedMessage, settledMessage } from '../../protocol/server-messages.js'

/**
 * A settlement whose commit failed is tried again after a back-off that
 * doubles from the first delay up to the last, for as long as the process
 * lives: a storage fault of a few seconds (a full disk) delays a payout, it
 * never strands it until a restart.
 */
export const SETTLE_RETRY_FIRST_MS = 100
export const SETTLE_RETRY_MAX_MS = 2000

/**
 * A drop's whole life, in one place:
 *
 *   accept   checks the bet, takes a nonce and an id (sequences), derives
 *            the drop seed, reserves the bet, releases the ball
 *   record   the tick's group commit writes its row (drop.js)
 *   apply    once committed: the reservation becomes a debit, the balance
 *            shown is the ledger's (money.js), the ball becomes visible
 *   announce `dropped` to everyone (the owner's copy with the balance)
 *   settle   the ball lands: its payout is written by a later tick's commit
 *   apply    once committed: the payout is credited, `settled` announced
 *
 * A drop the ledger refuses or cannot write is forgotten (nothing was
 * debited); a settlement that fails is retried with back-off until it is
 * written (start-up recovery settles what a stop leaves). Nothing is
 * announced before it is durable.
 */
export class DropLifecycle {
  /**
   * @param {object} options
   * @param {import('../config.js').Config} options.config
   * @param {any} options.store the ledger store
   * @param {import('./accounts.js').AccountBook} options.accounts
   * @param {import('../coordination/sequences.js').Sequences} options.sequences drop ids and nonces
   * @param {import('../coordination/account-feed.js').AccountFeed} options.feed tells other processes of committed balances
   * @param {import('../metrics.js').Metrics} options.metrics
   * @param {import('pino').Logger} options.log
   * @param {(rooms: Set<import('../rooms/room.js').Room>) => void} [options.onRoomsCommitted] told after each
   *   batch is applied (or refused) the rooms whose drops were in it: a frame held for them may go now
   */
  constructor ({ config, store, accounts, sequences, feed, metrics, log, onRoomsCommitted = () => {} }) {
    this.config = config
    this.onRoomsCommitted = onRoomsCommitted
    this.accounts = accounts
    this.sequences = sequences
    this.feed = feed
    this.metrics = metrics
    this.log = log
    this.ledger = new GroupCommit({
      store,
      metrics,
      log,
      ticksPerCommit: config.ledgerCommitTicks,
      onCommitted: (batch, outcome) => this._committed(batch, outcome),
      onFailed: (batch, error) => this._failed(batch, error)
    })
    /** @type {Set<import('./drop.js').Settlement>} landed, not yet committed */
    this.settling = new Set()
    /** @type {Map<import('./drop.js').Settlement, NodeJS.Timeout>} failed, waiting for their retry */
    this.retryTimers = new Map()
    /** @type {Array<() => void>} */
    this._retryWaiters = []
    /** Passed to Room.step: called for each ball that landed. */
    this.landed = (drop, landed, tick) => this._landed(drop, landed, tick)
  }

  /**
   * Accepts a drop: takes the player's next nonce, derives the drop seed,
   * reserves the bet and releases the ball at the room's current tick. The
   * drop is recorded by the tick's group commit and announced only after it.
   * Throws a GameError (and changes nothing) when the drop is refused.
   * @param {import('../realtime/connection.js').Connection} connection
   * @param {import('../rooms/room.js').Room} room
   * @param {{ bet: number, clientSeed?: string, ref?: any }} request
   * @returns {import('./drop.js').Drop}
   */
  accept (connection, room, { bet, clientSeed, ref }) {
    const { minBet, maxBet } = this.config
    if (!Number.isSafeInteger(bet) || bet < minBet || bet > maxBet) throw gameError('E_BAD_BET', `bet must be an integer from ${minBet} to ${maxBet}`)
    if (clientSeed !== undefined && !isValidClientSeed(clientSeed)) throw gameError('E_BAD_SEED')
    const account = connection.account
    // Its seed is about to be revealed (game/seed-changes.js): no drop may be recorded on it after that.
    if (account.seedRotations > 0) throw gameError('E_SEED_ROTATING')
    if (!account.dropLimiter.take()) throw gameError('E_RATE_LIMITED', `at most ${this.config.dropRate} drops per second`)
    if (!connection.ipLimits.drops.take()) throw gameError('E_RATE_LIMITED', `at most ${this.config.dropRatePerIp} drops per second from one address`)
    if (room.ballsInFlight >= this.config.maxBallsPerRoom) throw gameError('E_ROOM_FULL')
    if (betCost(bet) > account.available) throw gameError('E_INSUFFICIENT_FUNDS', `balance ${toCredits(account.available)} is lower than the bet ${bet}`)

    // Never given back, even if the drop fails to commit.
    const nonce = this.sequences.takeNonce(account.seed)
    const id = this.sequences.takeDropId()
    let clientSeedChange = null
    if (clientSeed !== undefined && clientSeed !== account.clientSeed) {
      clientSeedChange = { previous: account.clientSeed }
      account.clientSeed = clientSeed
    }
    const drop = createDrop({
      id,
      account,
      room,
      nonce,
      dropSeed: deriveDropSeed(account.seed.seed, account.clientSeed, nonce),
      bet,
      clientSeedChange,
      ref,
      origin: connection
    })
    account.reserved += betCost(bet)
    this.accounts.retain(account)
    room.release(drop)
    this.ledger.addDrop(drop)
    return drop
  }

  /** Drops whose ball landed but whose payout is not written yet (the ledger may be failing). */
  get unsettled () {
    this._forgetVoid()
    return this.settling.size
  }

  /** Settlements that failed at least once and are not written yet: /api/health reports `degraded`. */
  get settlementsWaiting () {
    this._forgetVoid()
    let waiting = 0
    for (const settlement of this.settling) if (settlement.attempts > 0) waiting++
    return waiting
  }

  /** A drop whose own batch failed is never settled (the group commit drops its settlement). */
  _forgetVoid () {
    for (const settlement of this.settling) if (settlement.drop.void) this.settling.delete(settlement)
  }

  /** Resolves when the next settlement's back-off ends and it is queued (at once if none waits). */
  nextRetry () {
    if (this.retryTimers.size === 0) return Promise.resolve()
    return new Promise((resolve) => this._retryWaiters.push(resolve))
  }

  _retry (settlement) {
    this.retryTimers.delete(settlement)
    this.ledger.addSettlement(settlement)
    for (const resolve of this._retryWaiters.splice(0)) resolve()
  }

  _landed (drop, landed, tick) {
    this._settle({
      drop,
      bucket: landed.bucket,
      multiplier: landed.multiplier,
      payout: payoutFor(drop.bet, landed.multiplier, drop.payoutRule),
      ticks: landed.ticks,
      stateHash: landed.stateHash,
      tick,
      settledAt: Date.now(),
      attempts: 0
    })
  }

  /** @param {import('./drop.js').Settlement} settlement */
  _settle (settlement) {
    this.settling.add(settlement)
    this.ledger.addSettlement(settlement)
  }

  /**
   * A batch is durable: apply it to the accounts and tell the rooms.
   * `outcome` says which drops the ledger refused and gives the committed
   * balances, which replace the cached ones; each message shows the balance
   * right after its own change, so a player's messages add up one by one.
   * @param {import('./drop.js').PendingBatch} batch
   * @param {import('./money.js').CommitOutcome} outcome
   */
  _committed ({ drops, settlements }, outcome) {
    const running = new RunningBalances(drops, settlements, outcome)
    /** rooms with events queued by this batch (SPECTATOR_EVENTS=immediate sends them at the end) */
    const touched = this.config.spectatorEvents === 'immediate' ? new Set() : null
    this.feed.balancesCommitted(outcome.balances.keys())
    // Counted once per batch: a labelled counter update costs about a microsecond.
    let announced = 0
    let bets = 0
    let payouts = 0
    /** rooms whose drops were in this batch, announced or refused */
    const rooms = new Set()
    for (const drop of drops) {
      const account = drop.account
      rooms.add(drop.room)
      const refused = outcome.rejected.get(drop.id)
      if (refused) {
        // A seed rotated by another process: the player hears of it once this one has the new seed, so dropping again works.
        const told = refused === 'E_SEED_ROTATED' ? this.feed.seedOutdated(account) : undefined
        this._refuse(drop, refused, refused === 'E_INSUFFICIENT_FUNDS' ? 'the balance no longer covers the bet; nothing was debited' : undefined, told)
        continue
      }
      account.reserved -= betCost(drop.bet)
      account.commits++
      account.balance = running.apply(account.playerId, -betCost(drop.bet))
      drop.announced = true
      drop.room.show(drop)
      announced++
      bets += drop.bet
      drop.room.dropAnnounced(drop, this._sendToOwnerConnections(drop, droppedMessage(drop), toCredits(account.balance)))
      touched?.add(drop.room)
    }
    for (const settlement of settlements) {
      const { drop, payout } = settlement
      const account = drop.account
      this.settling.delete(settlement)
      if (settlement.attempts > 0) {
        this.log.warn({ dropId: drop.id, attempts: settlement.attempts + 1 }, 'delayed settlement written')
        this.metrics.settlementsWaiting.set(this.settlementsWaiting)
      }
      account.commits++
      // Settled by another process (a shared ledger after a takeover): not credited here.
      account.balance = running.apply(account.playerId, outcome.settled.has(drop.id) ? payout : 0)
      this.accounts.release(account)
      payouts += payout
      const settled = settledMessage(drop, settlement, toCredits(payout))
      drop.room.dropSettled(drop, this._sendToOwnerConnections(drop, settled, toCredits(account.balance)))
      touched?.add(drop.room)
    }
    if (touched) for (const room of touched) room.flushEvents()
    if (rooms.size > 0) this.onRoomsCommitted(rooms)
    if (announced > 0) {
      this.metrics.drops.inc(announced)
      this.metrics.betTotal.inc(bets)
    }
    if (settlements.length > 0) {
      this.metrics.settles.inc(settlements.length)
      this.metrics.payoutTotal.inc(toCredits(payouts))
    }
  }

  /** A batch was rolled back: refuse its drops (nothing was debited) and retry its settlements. */
  _failed ({ drops, settlements }, error) {
    this.log.error({ err: error, drops: drops.length, settlements: settlements.length }, 'ledger commit failed')
    for (let i = drops.length - 1; i >= 0; i--) this._refuse(drops[i], 'E_INTERNAL', 'the drop could not be recorded; nothing was debited')
    if (drops.length > 0) this.onRoomsCommitted(new Set(drops.map((drop) => drop.room)))
    for (const settlement of settlements) {
      // Still in flight in the ledger (a stop now leaves it to start-up recovery): tried again after a back-off.
      const delay = Math.min(SETTLE_RETRY_MAX_MS, SETTLE_RETRY_FIRST_MS * 2 ** Math.min(settlement.attempts, 20))
      if (++settlement.attempts === 1) {
        this.log.error({ dropId: settlement.drop.id }, 'settlement not written; retrying until it is')
        this._sendToOwner(settlement.drop, 'E_INTERNAL', 'the settlement is delayed; it will be credited as soon as the ledger can be written')
      }
      this.retryTimers.set(settlement, setTimeout(() => this._retry(settlement), delay).unref())
    }
    if (settlements.length > 0) this.metrics.settlementsWaiting.set(this.settlementsWaiting)
  }

  /**
   * A room left this process (its lease went to another): its drops not yet
   * sent to the ledger never happened (refused, nothing debited); the rest
   * are recorded or being recorded, and their outcomes fixed, so their balls
   * are played out now and settled (a settlement is written only while its
   * drop is in flight, so the new owner's takeover and this never pay one
   * twice).
   * @param {import('../rooms/room.js').Room} room
   */
  roomGone (room) {
    for (const drop of this.ledger.withdrawDrops((d) => d.room === room)) {
      this._refuse(drop, 'E_ROOM_MOVING', 'the room moved to another process before the drop was recorded; nothing was debited')
    }
    let guard = 0
    while (room.ballsInFlight > 0 && guard++ < 100_000) room.step(this.landed)
  }

  /**
   * A drop that was not recorded: its ball is forgotten, nothing was
   * debited; the owner is told at once, or once `after` resolves.
   * @param {Promise<void>} [after]
   */
  _refuse (drop, code, message, after) {
    const account = drop.account
    drop.room.discard(drop)
    account.reserved -= betCost(drop.bet)
    if (drop.clientSeedChange && account.clientSeed === drop.clientSeed) account.clientSeed = drop.clientSeedChange.previous
    this.accounts.release(account)
    if (after) after.then(() => this._sendToOwner(drop, code, message))
    else this._sendToOwner(drop, code, message)
  }

  /**
   * Sends a drop event to all of the owner's connections (only the owner's
   * copy carries the balance, and only the connection that asked gets its
   * `ref` back): in every delivery mode, this is how a player's balance
   * changes reach it; `dropped` at once, `settled` when the socket's feed in
   * the drop's room says (Connection.sendSettled). The room's feeds tell everyone else, each in
   * its own way and pace (server/realtime/deliveries.js); the owner's
   * connections in the room get that copy too, and skip their own events.
   * @param {number} balance the owner's, in credits
   * @returns {string} the message as the room sees it (no balance), JSON
   */
  _sendToOwnerConnections (drop, message, balance) {
    // One JSON encoding per event: the owner's copy is the room's text with the balance
    // appended, the requester's with its ref too.
    const text = JSON.stringify(message)
    const owner = `${text.slice(0, -1)},"balance":${JSON.stringify(balance)}}`
    const type = message.type
    for (const client of drop.account.connections) {
      const copy = client === drop.origin && drop.ref !== undefined ? `${owner.slice(0, -1)},"ref":${JSON.stringify(drop.ref)}}` : owner
      // `settled`: the socket's feed in the drop's room decides when (it may ride in the room's next frame).
      if (type === 'settled') client.sendSettled(copy, drop.room)
      else client.sendEvent(copy, type)
    }
    return text
  }

  _sendToOwner (drop, code, message) {
    for (const client of drop.account.connections) {
      client.sendError(code, message, client === drop.origin ? drop.ref : undefined)
    }
  }
}
