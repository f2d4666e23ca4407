import { AccountBook } from './ledger/accounts.js'
import { GroupCommit } from './ledger/group-commit.js'
import { RoomRegistry } from './rooms/room-registry.js'
import { TickScheduler } from './rooms/tick-scheduler.js'
import { deriveDropSeed, isValidClientSeed } from './fairness/seeds.js'
import { payoutFor } from './fairness/payout.js'
import { gameError } from './errors.js'

/** Give up re-trying a settlement after this many failed commits; start-up recovery finishes it. */
const MAX_SETTLE_ATTEMPTS = 5

/**
 * @typedef {object} Drop one bet on one ball, from acceptance to settlement
 * @property {number} id @property {import('./ledger/accounts.js').Account} account
 * @property {string} playerId @property {import('./rooms/room.js').Room} room
 * @property {string} roomId @property {number} rows @property {string} risk
 * @property {string} engineVersion @property {string} seedId @property {string} serverSeedHash
 * @property {string} clientSeed @property {number} nonce @property {string} dropSeed
 * @property {number} bet @property {number} createdAt ms
 * @property {number} startTick @property {number} slot set by Room.release
 * @property {boolean} announced its row is committed and `dropped` was sent
 * @property {boolean} void its row could not be committed: ignored when it lands
 * @property {{ previous: string } | null} clientSeedChange the drop set a new client seed
 * @property {any} ref the client's ref, echoed to the connection that asked
 * @property {import('./realtime/connection.js').Connection | null} origin
 */

/**
 * The game: rooms on one clock, player accounts, and the ledger that
 * records every drop before it is announced. Each tick steps every room,
 * seals the tick's ledger batch and broadcasts the snapshots that are due.
 */
export class Arena {
  /**
   * @param {object} options
   * @param {import('./config.js').Config} options.config
   * @param {any} options.store the ledger store (see store/sqlite-store.js)
   * @param {import('./metrics.js').Metrics} options.metrics
   * @param {import('pino').Logger} options.log
   * @param {number} options.firstDropId ids continue from the ledger's highest
   * @param {number} [options.tickRate] wall-clock ticks per second (60; tests may run faster)
   */
  constructor ({ config, store, metrics, log, firstDropId, tickRate = 60 }) {
    this.config = config
    this.store = store
    this.metrics = metrics
    this.log = log
    this.nextDropId = firstDropId
    this.accepting = true
    this.accounts = new AccountBook({ store, limits: { dropRate: config.dropRate, dropBurst: config.dropBurst, joinRate: config.joinRate } })
    this.rooms = new RoomRegistry({
      snapshotEvery: 60 / config.snapshotHz,
      onChange: (room) => {
        metrics.rooms.set(this.rooms.size)
        if (this.cluster && this.rooms.get(room.id) !== room) this.cluster.roomDisposed(room.id)
      }
    })
    /** Set when clustered (server/cluster/cluster-node.js): room leases, directory, takeover. */
    this.cluster = null
    /** The shared ledger hands out drop ids and nonces when clustered (server/cluster/shared-ledger.js). */
    this.sharedLedger = store.shared ? store : null
    this.ledger = new GroupCommit({
      store,
      metrics,
      log,
      onCommitted: (batch, outcome) => this._committed(batch, outcome),
      onFailed: (batch, error) => this._failed(batch, error)
    })
    /** Ping every connection this often (in 60 Hz ticks, from WS_HEARTBEAT_MS) and drop those that did not answer the last ping. */
    this.heartbeatTicks = Math.max(1, Math.round(config.wsHeartbeatMs * 60 / 1000))
    this.scheduler = new TickScheduler({ onTick: () => this.tick(), tickRate, maxCatchUp: config.maxCatchUpTicks, metrics, log })
    /** @type {Set<import('./realtime/connection.js').Connection>} */
    this.connections = new Set()
    this._onLanded = (drop, landed, tick) => this._landed(drop, landed, tick)
  }

  start () {
    this.scheduler.start()
  }

  /** One 60 Hz tick for every room. */
  tick () {
    let inFlight = 0
    for (const room of this.rooms.values()) {
      try {
        room.step(this._onLanded)
      } catch (error) {
        // One broken room must not stop the others (they come after it in this loop).
        this.log.error({ err: error, room: room.id }, 'room step failed')
      }
      inFlight += room.ballsInFlight
    }
    this.ledger.flush()
    for (const room of this.rooms.values()) {
      if (room.clients.size === 0 || !room.snapshotDue) continue
      const { frame, events } = room.encodeFrame()
      if (frame !== null) for (const client of room.clients) client.sendRoomFrame(frame, events)
      else if (events !== null) this._sendEvents(room, events)
    }
    this.rooms.disposeIdle()
    this.metrics.ballsInFlight.set(inFlight)
    if (this.scheduler.ticks % this.heartbeatTicks === this.heartbeatTicks - 1) {
      for (const connection of this.connections) connection.heartbeat()
    }
  }

  // ---- connections and rooms ------------------------------------------

  /** @param {import('./realtime/connection.js').Connection} connection */
  connected (connection) {
    this.connections.add(connection)
    this.metrics.clients.set(this.connections.size)
  }

  /** @param {import('./realtime/connection.js').Connection} connection */
  disconnected (connection) {
    if (connection.room) this.leave(connection)
    this.connections.delete(connection)
    this.metrics.clients.set(this.connections.size)
  }

  /**
   * @param {import('./realtime/connection.js').Connection} connection
   * @param {unknown} roomId
   * @returns {object | Promise<object>} the `joined` message (a promise when clustered and the room runs elsewhere)
   */
  join (connection, roomId) {
    if (!this.accepting) throw gameError('E_UNAVAILABLE')
    // Clustered: a room not running here is claimed first (async), or the reply says where it runs.
    if (this.cluster && !this.rooms.get(/** @type {string} */ (roomId))) return this.cluster.join(connection, roomId)
    return this.joinLocal(connection, roomId)
  }

  /** Joins a room this process runs (or creates it). @param {any} connection @param {unknown} roomId */
  joinLocal (connection, roomId) {
    if (!this.accepting) throw gameError('E_UNAVAILABLE')
    const room = this.rooms.getOrCreate(roomId)
    if (connection.room && connection.room !== room) this.leave(connection)
    // Events queued so far concern balls the joiner gets in `balls`: the others get them now.
    const queued = room.takeEvents()
    if (queued !== null) this._sendEvents(room, queued)
    room.clients.add(connection)
    connection.room = room
    return {
      type: 'joined',
      room: room.id,
      board: room.board,
      tick: room.tick,
      tickRate: 60,
      snapshotEvery: room.snapshotEvery,
      engineVersion: room.board.engineVersion,
      balls: room.ballStates()
    }
  }

  /** @param {import('./realtime/connection.js').Connection} connection */
  leave (connection) {
    const room = connection.room
    if (!room) throw gameError('E_NOT_IN_ROOM', 'not in a room')
    room.clients.delete(connection)
    connection.room = null
    return room.id
  }

  // ---- drops ------------------------------------------------------------

  /**
   * Accepts a drop: takes the player's next nonce, derives the drop seed,
   * reserves the bet and releases the ball at the room's current tick. The
   * drop is recorded by the tick's group commit and announced only after it.
   * Throws a GameError (and changes nothing) when the drop is refused.
   * @param {import('./realtime/connection.js').Connection} connection
   * @param {{ bet: number, clientSeed?: string, ref?: any }} request
   */
  drop (connection, { bet, clientSeed, ref }) {
    if (!this.accepting) throw gameError('E_UNAVAILABLE')
    const room = connection.room
    if (!room) throw gameError('E_NOT_IN_ROOM')
    const { minBet, maxBet } = this.config
    if (!Number.isSafeInteger(bet) || bet < minBet || bet > maxBet) throw gameError('E_BAD_BET', `bet must be an integer from ${minBet} to ${maxBet}`)
    if (clientSeed !== undefined && !isValidClientSeed(clientSeed)) throw gameError('E_BAD_SEED')
    const account = connection.account
    if (!account.dropLimiter.take()) throw gameError('E_RATE_LIMITED', `at most ${this.config.dropRate} drops per second`)
    if (connection.ipLimits && !connection.ipLimits.drops.take()) throw gameError('E_RATE_LIMITED', `at most ${this.config.dropRatePerIp} drops per second from one address`)
    if (room.ballsInFlight >= this.config.maxBallsPerRoom) throw gameError('E_ROOM_FULL')
    if (bet > account.available) throw gameError('E_INSUFFICIENT_FUNDS', `balance ${account.available} is lower than the bet ${bet}`)

    const seed = account.seed
    // Clustered, nonces and drop ids come from blocks reserved in the shared ledger.
    const nonce = this.sharedLedger ? this.sharedLedger.takeNonce(seed) : seed.nextNonce++ // never given back, even if the drop fails to commit
    const id = this.sharedLedger ? this.sharedLedger.takeDropId() : this.nextDropId++
    let clientSeedChange = null
    if (clientSeed !== undefined && clientSeed !== account.clientSeed) {
      clientSeedChange = { previous: account.clientSeed }
      account.clientSeed = clientSeed
    }
    /** @type {Drop} */
    const drop = {
      id,
      account,
      playerId: account.playerId,
      room,
      roomId: room.id,
      rows: room.rows,
      risk: room.risk,
      engineVersion: room.board.engineVersion,
      seedId: seed.id,
      serverSeedHash: seed.hash,
      clientSeed: account.clientSeed,
      nonce,
      dropSeed: deriveDropSeed(seed.seed, account.clientSeed, nonce),
      bet,
      createdAt: Date.now(),
      startTick: 0,
      slot: -1,
      announced: false,
      void: false,
      clientSeedChange,
      ref,
      origin: connection
    }
    account.reserved += bet
    this.accounts.retain(account)
    room.release(drop)
    this.ledger.addDrop(drop)
    return drop
  }

  _landed (drop, landed, tick) {
    this.ledger.addSettlement({
      drop,
      bucket: landed.bucket,
      multiplier: landed.multiplier,
      payout: payoutFor(drop.bet, landed.multiplier),
      ticks: landed.ticks,
      stateHash: landed.stateHash,
      tick,
      settledAt: Date.now(),
      attempts: 0
    })
  }

  /**
   * A batch is durable: apply it to the accounts and tell the rooms. With the
   * shared ledger (clustered) `outcome` says which drops the database refused
   * and gives the committed balances, which replace the cached ones.
   * @param {{ drops: Drop[], settlements: any[] }} batch
   * @param {{ rejected: Map<number, string>, settled: Set<number>, balances: Map<string, number> }} [outcome]
   */
  _committed ({ drops, settlements }, outcome) {
    // Clustered: each message shows the balance right after its own change, worked back from
    // the committed one, so a player's `dropped`/`settled` in one batch still add up one by one.
    const running = outcome ? balancesBefore(drops, settlements, outcome) : null
    /** rooms with events queued by this batch (SPECTATOR_EVENTS=immediate sends them at the end) */
    const touched = this.config.spectatorEvents === 'immediate' ? new Set() : null
    if (outcome) this.cluster?.balances.committed(outcome.balances.keys())
    for (const drop of drops) {
      const account = drop.account
      const refused = outcome?.rejected.get(drop.id)
      if (refused) {
        this._refuse(drop, refused, refused === 'E_INSUFFICIENT_FUNDS' ? 'the balance no longer covers the bet; nothing was debited' : undefined)
        continue
      }
      account.reserved -= drop.bet
      account.commits++
      account.balance = running?.has(account.playerId) ? change(running, account.playerId, -drop.bet) : account.balance - drop.bet
      drop.announced = true
      drop.room.show(drop)
      this.metrics.drops.inc()
      this.metrics.betTotal.inc(drop.bet)
      this._broadcast(drop, {
        type: 'dropped',
        room: drop.roomId,
        dropId: drop.id,
        player: drop.playerId,
        serverSeedHash: drop.serverSeedHash,
        clientSeed: drop.clientSeed,
        nonce: drop.nonce,
        dropSeed: drop.dropSeed,
        engineVersion: drop.engineVersion,
        startTick: drop.startTick,
        bet: drop.bet,
        slot: drop.slot
      }, account.balance)
      touched?.add(drop.room)
    }
    for (const settlement of settlements) {
      const { drop, payout } = settlement
      const account = drop.account
      account.commits++
      if (!running) account.balance += payout
      else if (running.has(account.playerId)) account.balance = change(running, account.playerId, outcome.settled.has(drop.id) ? payout : 0)
      this.accounts.release(account)
      this.metrics.settles.inc()
      this.metrics.payoutTotal.inc(payout)
      this._broadcast(drop, {
        type: 'settled',
        room: drop.roomId,
        dropId: drop.id,
        player: drop.playerId,
        bet: drop.bet,
        bucket: settlement.bucket,
        multiplier: settlement.multiplier,
        payout,
        ticks: settlement.ticks,
        tick: settlement.tick,
        stateHash: settlement.stateHash
      }, account.balance)
      touched?.add(drop.room)
    }
    if (touched) {
      for (const room of touched) {
        const events = room.takeEvents()
        if (events !== null) this._sendEvents(room, events)
      }
    }
  }

  /** A batch was rolled back: refuse its drops (nothing was debited) and retry its settlements. */
  _failed ({ drops, settlements }, error) {
    this.log.error({ err: error, drops: drops.length, settlements: settlements.length }, 'ledger commit failed')
    for (let i = drops.length - 1; i >= 0; i--) this._refuse(drops[i], 'E_INTERNAL', 'the drop could not be recorded; nothing was debited')
    for (const settlement of settlements) {
      if (++settlement.attempts < MAX_SETTLE_ATTEMPTS) {
        this.ledger.addSettlement(settlement)
        continue
      }
      // Left in flight in the ledger: start-up recovery settles it from its seed.
      this.log.error({ dropId: settlement.drop.id }, 'giving up settling drop until restart')
      this.accounts.release(settlement.drop.account)
      this._sendToOwner(settlement.drop, 'E_INTERNAL', 'the settlement is delayed; it will be credited when the server restarts')
    }
  }

  /** A drop that was not recorded: its ball is forgotten, nothing was debited. */
  _refuse (drop, code, message) {
    const account = drop.account
    drop.room.discard(drop)
    account.reserved -= drop.bet
    if (drop.clientSeedChange && account.clientSeed === drop.clientSeed) account.clientSeed = drop.clientSeedChange.previous
    this.accounts.release(account)
    this._sendToOwner(drop, code, message)
  }

  /**
   * Sends a drop event to all of the owner's connections at once (only the
   * owner's copy carries the balance, and only the connection that asked
   * gets its `ref` back) and queues it for everyone in the room, who get it
   * with the room's next snapshot (≤ 1/SNAPSHOT_HZ later) in one frame
   * with the other events. The owner's connections in the room get that
   * copy too, and skip their own player's events.
   */
  _broadcast (drop, message, balance) {
    const account = drop.account
    const owner = JSON.stringify({ ...message, balance })
    const type = message.type
    drop.room.queueEvent(JSON.stringify(message))
    for (const client of account.connections) {
      if (client === drop.origin && drop.ref !== undefined) client.sendEvent(JSON.stringify({ ...message, balance, ref: drop.ref }), type)
      else client.sendEvent(owner, type)
    }
  }

  /** A room's queued events on their own, as `{type:"events"}`: no snapshot goes with them. */
  _sendEvents (room, events) {
    const text = room.eventsMessage(events)
    for (const client of room.clients) client.sendEvent(text, 'events')
  }

  _sendToOwner (drop, code, message) {
    for (const client of drop.account.connections) {
      client.sendError(code, message, client === drop.origin ? drop.ref : undefined)
    }
  }

  /**
   * This process may no longer run `roomId` (clustered: its lease went to
   * another process). Its players are told to join it again; its drops not
   * yet sent to the ledger never happened (refused, nothing debited); the
   * rest are recorded or being recorded, and their outcomes fixed, so their
   * balls are played out now and settled (a settlement is written only
   * while its drop is in flight, so the new owner's takeover and this never
   * pay one twice).
   * @param {string} roomId
   */
  evictRoom (roomId) {
    const room = this.rooms.remove(roomId)
    if (!room) return
    for (const client of room.clients) {
      client.room = null
      client.sendError('E_ROOM_MOVING', 'this process lost the room; join it again', undefined, { room: roomId, retryAfterMs: 0 })
    }
    room.clients.clear()
    for (const drop of this.ledger.withdrawDrops((d) => d.room === room)) {
      this._refuse(drop, 'E_ROOM_MOVING', 'the room moved to another process before the drop was recorded; nothing was debited')
    }
    let guard = 0
    while (room.ballsInFlight > 0 && guard++ < 100_000) room.step(this._onLanded)
  }

  // ---- shutdown -----------------------------------------------------------

  /** Stops taking joins and drops (they get E_UNAVAILABLE). */
  stopAccepting () {
    this.accepting = false
  }

  /**
   * Graceful shutdown: no new drops; every ball in flight is played to the
   * end at once (its outcome is fixed by its seed), settled and committed;
   * then all connections are closed with 1001 (going away).
   */
  async close () {
    this.stopAccepting()
    this.scheduler.stop()
    let guard = 0
    while ([...this.rooms.values()].some((room) => room.ballsInFlight > 0) && guard++ < 100_000) {
      for (const room of this.rooms.values()) if (room.ballsInFlight > 0) room.step(this._onLanded)
      this.ledger.flush()
    }
    await this.ledger.drain()
    for (const connection of [...this.connections]) connection.close(1001, 'server shutting down')
  }
}

/**
 * Each player's balance before a committed shared-ledger batch: the
 * committed balance less what the batch itself changed (accepted bets,
 * credited payouts).
 * @returns {Map<string, number>}
 */
function balancesBefore (drops, settlements, outcome) {
  const before = new Map(outcome.balances)
  for (const drop of drops) {
    if (!outcome.rejected.has(drop.id) && before.has(drop.playerId)) before.set(drop.playerId, before.get(drop.playerId) + drop.bet)
  }
  for (const { drop, payout } of settlements) {
    if (outcome.settled.has(drop.id) && before.has(drop.playerId)) before.set(drop.playerId, before.get(drop.playerId) - payout)
  }
  return before
}

/** Applies `amount` to a player's running balance; returns the new balance. */
function change (running, playerId, amount) {
  const balance = running.get(playerId) + amount
  running.set(playerId, balance)
  return balance
}
