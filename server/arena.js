import { parseRoomId } from '../protocol/room-id.js'
import { AccountBook } from './game/accounts.js'
import { RoomRegistry } from './rooms/room-registry.js'
import { TickScheduler, SIMULATION_HZ } from './rooms/tick-scheduler.js'
import { DropLifecycle } from './game/drop-lifecycle.js'
import { gameError } from './errors.js'
import { deliveryNamed, emptyTally } from './realtime/deliveries.js'
import { joinedMessage, balanceMessage } from '../protocol/server-messages.js'
import { toCredits } from './game/money.js'
import { DESYNC_CHECK_SECONDS } from './realtime/delivery-seeds.js'
import { HeartbeatSchedule } from './realtime/heartbeat-schedule.js'

/**
 * The game: rooms on one clock and the connections in them. Each tick steps
 * every room, seals the tick's ledger batch and lets each room's feeds
 * (server/realtime/deliveries.js) send what is due. A drop's life (money,
 * record, announcements) is the drop lifecycle's (game/drop-lifecycle.js). Which rooms this process may
 * run is room ownership's, where nonces and drop ids come from the sequences', and what other processes
 * change in accounts reaches them through the account feed (coordination/: one small interface each,
 * the same alone or clustered); none of them sees the arena, only the services it hands them.
 */
export class Arena {
  /**
   * @param {object} options
   * @param {import('./config.js').Config} options.config
   * @param {any} options.store the ledger store (see store/sqlite-store.js)
   * @param {import('./coordination/room-ownership.js').RoomOwnership} options.ownership
   * @param {import('./coordination/sequences.js').Sequences} options.sequences
   * @param {import('./coordination/account-feed.js').AccountFeed} options.feed
   * @param {import('./metrics.js').Metrics} options.metrics
   * @param {import('pino').Logger} options.log
   * @param {number} [options.tickRate] wall-clock ticks per second (SIMULATION_HZ; tests may run faster)
   */
  constructor ({ config, store, ownership, sequences, feed, metrics, log, tickRate = SIMULATION_HZ }) {
    this.config = config
    this.store = store
    this.ownership = ownership
    this.sequences = sequences
    this.feed = feed
    this.metrics = metrics
    this.log = log
    this.accepting = true
    this.accounts = new AccountBook({ store, limits: { dropRate: config.dropRate, dropBurst: config.dropBurst, joinRate: config.joinRate } })
    this.rooms = new RoomRegistry({
      snapshotEvery: SIMULATION_HZ / config.snapshotHz,
      eventEvery: SIMULATION_HZ / config.eventHz,
      checkEvery: DESYNC_CHECK_SECONDS * SIMULATION_HZ,
      onChange: (room) => {
        metrics.rooms.set(this.rooms.size)
        if (this.rooms.get(room.id) !== room) ownership.disposed(room.id)
      }
    })
    this.drops = new DropLifecycle({ config, store, accounts: this.accounts, sequences, feed, metrics, log, onRoomsCommitted: (rooms) => this._roomsCommitted(rooms) })
    /** The tick's group commit; seed changes and lease releases queue behind the drops in it. */
    this.ledger = this.drops.ledger
    /** Pings each connection every WS_HEARTBEAT_MS (in ticks), a few a tick, and drops those that did not answer the last ping. */
    this.heartbeats = new HeartbeatSchedule(Math.max(1, Math.round(config.wsHeartbeatMs * SIMULATION_HZ / 1000)))
    this.scheduler = new TickScheduler({ onTick: () => this.tick(), tickRate, maxCatchUp: config.maxCatchUpTicks, metrics, log })
    /** @type {Set<import('./realtime/connection.js').Connection>} */
    this.connections = new Set()
    this._tally = emptyTally()
  }

  /**
   * Before the clock: the first drop ids, the feed of other processes'
   * account changes, then room ownership (which settles what the last run left).
   */
  async start () {
    await this.sequences.start()
    await this.feed.start({ accounts: this.accounts, onBalanceChanged: (account, balance) => this._balanceChangedElsewhere(account, balance) })
    await this.ownership.start({ rooms: this.rooms, ledger: this.ledger, onRoomLost: (roomId) => this.evictRoom(roomId) })
  }

  /** Another process committed this balance for an account held here: shown to the player's connections. */
  _balanceChangedElsewhere (account, balance) {
    account.balance = balance
    for (const connection of account.connections) connection.sendJson(balanceMessage(toCredits(balance)))
  }

  /** Starts the clock. */
  run () {
    this.scheduler.start()
  }

  /** Balls of live drops in flight in every room of this process. */
  get ballsInFlight () {
    let count = 0
    for (const room of this.rooms.values()) count += room.ballsInFlight
    return count
  }

  /**
   * Drops recorded here and not settled yet: balls in flight, and landed
   * balls whose payout is not written (a failing ledger retries it).
   */
  get unsettledDrops () {
    return this.ballsInFlight + this.drops.unsettled
  }

  /**
   * @typedef {{ accepting: boolean, settlementsWaiting: number, store: string, tick: number, rooms: number }} ArenaHealth
   * @returns {ArenaHealth} what GET /api/health reports
   */
  health () {
    return { accepting: this.accepting, settlementsWaiting: this.drops.settlementsWaiting, store: this.store.kind, tick: this.scheduler.ticks, rooms: this.rooms.size }
  }

  /** One tick for every room. */
  tick () {
    let inFlight = 0
    const landed = this.drops.landed
    for (const room of this.rooms.inStepOrder()) {
      try {
        room.step(landed)
      } catch (error) {
        // One broken room must not stop the others (they come after it in this loop).
        this.log.error({ err: error, room: room.id }, 'room step failed')
      }
      inFlight += room.ballsInFlight
    }
    this.ledger.flush()
    const tally = this._tally
    for (const room of this.rooms.values()) {
      if (room.clients.size === 0) continue
      try {
        room.deliver(tally)
      } catch (error) {
        this.log.error({ err: error, room: room.id }, 'room delivery failed')
      }
    }
    this._count(tally)
    this.rooms.disposeIdle()
    this.metrics.ballsInFlight.set(inFlight)
    this.heartbeats.tick(this.scheduler.ticks)
  }

  /** A batch with drops of these rooms is done (between two ticks): their feeds may send what waited for it. */
  _roomsCommitted (rooms) {
    for (const room of rooms) {
      try {
        room.batchCommitted(this._tally)
      } catch (error) {
        this.log.error({ err: error, room: room.id }, 'room delivery failed')
      }
    }
  }

  /** The tick's frames, counted once (not per socket). @param {import('./realtime/deliveries.js').DeliveryTally} tally */
  _count (tally) {
    if (tally.snapshotFrames > 0) this.metrics.snapshotOut.inc(tally.snapshotFrames)
    if (tally.eventFrames > 0) this.metrics.dropEventsOut.inc(tally.eventFrames)
    if (tally.snapshotBytes + tally.eventBytes > 0) this.metrics.bytesOut.inc(tally.snapshotBytes + tally.eventBytes)
    tally.snapshotFrames = tally.snapshotBytes = tally.eventFrames = tally.eventBytes = 0
  }

  // ---- connections and rooms ------------------------------------------

  /** @param {import('./realtime/connection.js').Connection} connection */
  connected (connection) {
    this.connections.add(connection)
    this.heartbeats.add(connection)
    this.metrics.clients.set(this.connections.size)
  }

  /** @param {import('./realtime/connection.js').Connection} connection */
  disconnected (connection) {
    if (connection.room) this.leave(connection)
    this.connections.delete(connection)
    this.heartbeats.remove(connection)
    this.metrics.clients.set(this.connections.size)
  }

  /**
   * Joins a room, creating it here if this process may run it; a room it
   * may not run yet is claimed first (async), or the error says where it runs.
   * @param {import('./realtime/connection.js').Connection} connection
   * @param {unknown} roomId
   * @param {string} [deliveryName] `join.delivery` (schema-checked): how this socket is fed in the room
   * @returns {object | Promise<object>} the `joined` message: itself when the room runs here, on purpose,
   *   so a `drop` that follows the `join` in the same TCP chunk (ws emits their messages in one call
   *   stack, with no microtask between them) finds the room joined; a Promise only when it must be claimed
   */
  join (connection, roomId, deliveryName) {
    if (!this.accepting) throw gameError('E_UNAVAILABLE')
    const delivery = deliveryNamed(deliveryName)
    const id = /** @type {string} */ (roomId)
    if (this.rooms.get(id) || !parseRoomId(roomId) || this.ownership.owns(id)) return this._join(connection, roomId, delivery)
    return this.ownership.claim(id).then(() => {
      if (connection.closed) throw gameError('E_UNAVAILABLE', 'connection closed')
      return this._join(connection, id, delivery)
    })
  }

  /** @param {any} connection @param {unknown} roomId @param {import('./realtime/deliveries.js').Delivery} delivery */
  _join (connection, roomId, delivery) {
    if (!this.accepting) throw gameError('E_UNAVAILABLE')
    const room = this.rooms.getOrCreate(roomId)
    if (connection.room) this.leave(connection)
    connection.feed = room.join(connection, delivery)
    connection.room = room
    return joinedMessage({
      room: room.id,
      delivery: delivery.name,
      board: room.board,
      tick: room.tick,
      tickRate: SIMULATION_HZ,
      snapshotEvery: room.snapshotEvery,
      engineVersion: room.board.engineVersion,
      balls: room.ballStates()
    }, delivery.joinedFields(room))
  }

  /** @param {import('./realtime/connection.js').Connection} connection */
  leave (connection) {
    const room = connection.room
    if (!room) throw gameError('E_NOT_IN_ROOM', 'not in a room')
    room.leave(connection, connection.feed)
    connection.room = null
    connection.feed = null
    return room.id
  }

  /**
   * A drop from a connection in a room (game/drop-lifecycle.js). Throws a
   * GameError (and changes nothing) when the drop is refused.
   * @param {import('./realtime/connection.js').Connection} connection
   * @param {{ bet: number, clientSeed?: string, ref?: any }} request
   */
  drop (connection, request) {
    if (!this.accepting) throw gameError('E_UNAVAILABLE')
    const room = connection.room
    if (!room) throw gameError('E_NOT_IN_ROOM')
    return this.drops.accept(connection, room, request)
  }

  /**
   * This process may no longer run `roomId` (its lease went to another
   * process). Its players are told to join it again; its drops are refused
   * or played out and settled (DropLifecycle.roomGone).
   * @param {string} roomId
   */
  evictRoom (roomId) {
    const room = this.rooms.remove(roomId)
    if (!room) return
    for (const client of [...room.clients]) {
      room.leave(client, client.feed)
      client.room = null
      client.feed = null
      client.sendError('E_ROOM_MOVING', 'this process lost the room; join it again', undefined, { room: roomId, retryAfterMs: 0 })
    }
    this.drops.roomGone(room)
  }

  // ---- shutdown -----------------------------------------------------------

  /** Stops taking joins and drops (they get E_UNAVAILABLE). */
  stopAccepting () {
    this.accepting = false
  }

  /**
   * Graceful shutdown: no new drops; every ball in flight is played to the
   * end at once (its outcome is fixed by its seed), settled and committed
   * (a settlement the ledger refuses is tried again after its back-off until
   * it is written or the caller's shutdown timeout gives up: start-up
   * recovery then settles it); then all connections are closed with 1001.
   */
  async close () {
    this.stopAccepting()
    this.scheduler.stop()
    const landed = this.drops.landed
    let guard = 0
    while (this.ballsInFlight > 0 && guard++ < 100_000) {
      for (const room of this.rooms.values()) if (room.ballsInFlight > 0) room.step(landed)
      this.ledger.flush()
    }
    await this.ledger.drain()
    // Only while a retry is pending: anything else still counted is reported by the caller, not waited for.
    while (this.drops.unsettled > 0 && this.drops.retryTimers.size > 0) {
      await this.drops.nextRetry()
      await this.ledger.drain()
    }
    for (const connection of [...this.connections]) connection.close(1001, 'server shutting down')
  }
}
