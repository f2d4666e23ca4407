import { DropSimulator } from '../../engine/index.js'
import { publicDropFacts } from '../../protocol/server-messages.js'

/** Defaults of what the feeds pace themselves by (config: SNAPSHOT_HZ, EVENT_HZ; a 2 s desync check). */
const DEFAULT_EVENT_EVERY = 15
const DEFAULT_CHECK_EVERY = 120

/**
 * One board, its simulator and the connections watching it. Lifecycle:
 * created on the first join, stepped by the arena's scheduler, disposed by
 * the registry once it has no clients and no balls in flight.
 *
 * A ball's slot is its body id in the simulator: small, reused lowest first
 * once the ball has landed. A ball is *visible* (in snapshots and in
 * `joined`) only after its drop has been recorded and announced, so every
 * slot a client sees has been named in a `dropped` message first.
 *
 * Its sockets are grouped by delivery mode (server/realtime/deliveries.js),
 * one feed per mode: the room tells the feeds what happened, each feed
 * decides what its sockets get.
 */
export class Room {
  /**
   * @param {object} options
   * @param {string} options.id
   * @param {import('../../engine/board.js').Board} options.board
   * @param {number} options.snapshotEvery ticks between snapshots
   * @param {number} [options.snapshotPhase] offset so rooms' snapshots (and event frames) fall on different ticks
   * @param {number} [options.eventEvery] ticks between two drop-events frames of the seeds delivery (60 / EVENT_HZ)
   * @param {number} [options.checkEvery] most ticks between two desync checks while balls are in flight
   */
  constructor ({ id, board, snapshotEvery, snapshotPhase = 0, eventEvery = DEFAULT_EVENT_EVERY, checkEvery = DEFAULT_CHECK_EVERY }) {
    this.id = id
    this.board = board
    this.rows = board.rows
    this.risk = board.risk
    this.simulator = new DropSimulator(board)
    /** Ticks stepped since the room was created. A ball released at tick T lands at T + ticks. */
    this.tick = 0
    this.snapshotEvery = snapshotEvery
    this.snapshotPhase = snapshotPhase % snapshotEvery
    this.eventEvery = eventEvery
    this.checkEvery = checkEvery
    /** Every socket in the room, whatever its mode. @type {Set<any>} */
    this.clients = new Set()
    /** One feed per delivery mode with sockets here. @type {Map<import('../realtime/deliveries.js').Delivery, import('../realtime/deliveries.js').RoomFeed>} */
    this.feeds = new Map()
    /** @type {(import('../game/drop.js').Drop | undefined)[]} drop by slot, while in flight */
    this.balls = []
    this.visible = new Uint8Array(64)
    this.visibleCount = 0
    this._discarded = 0
  }

  /**
   * Adds a socket, fed by `delivery` (its mode, chosen at join).
   * @param {any} connection @param {import('../realtime/deliveries.js').Delivery} delivery
   * @returns {import('../realtime/deliveries.js').RoomFeed} the socket's feed
   */
  join (connection, delivery) {
    let feed = this.feeds.get(delivery)
    if (!feed) {
      feed = delivery.createFeed(this)
      this.feeds.set(delivery, feed)
    }
    feed.beforeJoin()
    feed.clients.add(connection)
    this.clients.add(connection)
    return feed
  }

  /** @param {any} connection @param {import('../realtime/deliveries.js').RoomFeed} feed the one join() gave it */
  leave (connection, feed) {
    feed.leave(connection)
    this.clients.delete(connection)
  }

  /** A drop was recorded: every feed hears of it. @param {import('../game/drop.js').Drop} drop @param {string} text its `dropped`, no balance, JSON */
  dropAnnounced (drop, text) {
    for (const feed of this.feeds.values()) feed.dropAnnounced(drop, text)
  }

  /** A drop was credited. @param {import('../game/drop.js').Drop} drop @param {string} text its `settled`, no balance, JSON */
  dropSettled (drop, text) {
    for (const feed of this.feeds.values()) feed.dropSettled(drop, text)
  }

  /** SPECTATOR_EVENTS=immediate: a batch just committed. */
  flushEvents () {
    for (const feed of this.feeds.values()) feed.flushNow()
  }

  /**
   * A batch with drops of this room was committed or refused (between two
   * ticks): each feed may send what waited for it.
   * @param {import('../realtime/deliveries.js').DeliveryTally} tally
   */
  batchCommitted (tally) {
    for (const feed of this.feeds.values()) feed.batchCommitted(tally)
  }

  /** After the tick's step and commit hand-over: each feed sends what is due. @param {import('../realtime/deliveries.js').DeliveryTally} tally */
  deliver (tally) {
    for (const feed of this.feeds.values()) feed.afterTick(tally)
  }

  /** Balls of live drops in flight (discarded ones excluded). */
  get ballsInFlight () { return this.simulator.inFlight - this._discarded }

  get isIdle () { return this.clients.size === 0 && this.simulator.inFlight === 0 }

  /**
   * Puts a drop's ball on the board at the current tick.
   * @param {import('../game/drop.js').Drop} drop
   */
  release (drop) {
    drop.startTick = this.tick
    const slot = this.simulator.addDrop(drop.dropSeed, drop)
    drop.slot = slot
    this.balls[slot] = drop
    if (slot >= this.visible.length) {
      const grown = new Uint8Array(Math.max(slot + 1, this.visible.length * 2))
      grown.set(this.visible)
      this.visible = grown
    }
  }

  /**
   * Whether a drop released before `tick` (its start tick lower) still waits
   * for its commit: neither announced nor voided, its ball still falling.
   * The seeds feed holds a due frame for such drops (delivery-seeds.js).
   * @param {number} tick
   */
  awaitsCommitBefore (tick) {
    // Asked on due ticks only (a few times a second): a look at the balls in flight, no state kept for it.
    const balls = this.balls
    for (let slot = 0; slot < balls.length; slot++) {
      const drop = balls[slot]
      if (drop !== undefined && !drop.announced && !drop.void && drop.startTick < tick) return true
    }
    return false
  }

  /** Makes an announced drop's ball visible, if it is still in flight. @param {import('../game/drop.js').Drop} drop */
  show (drop) {
    if (this.balls[drop.slot] !== drop || this.visible[drop.slot] === 1) return
    this.visible[drop.slot] = 1
    this.visibleCount++
  }

  /**
   * Forgets a drop whose ledger record failed. Its ball keeps falling (the
   * simulator has no way to remove one) but is never shown, counted against
   * the room's limit, or settled.
   * @param {import('../game/drop.js').Drop} drop
   */
  discard (drop) {
    if (drop.void) return
    drop.void = true
    if (this.balls[drop.slot] === drop) this._discarded++
  }

  /**
   * Advances one tick. `onLanded(drop, landed, tick)` runs for each ball
   * that landed, with `tick` = the room tick after this step.
   * @param {(drop: any, landed: import('../../engine/drop-simulator.js').LandedDrop, tick: number) => void} onLanded
   */
  step (onLanded) {
    const landed = this.simulator.step()
    this.tick++
    for (let i = 0; i < landed.length; i++) {
      const ball = landed[i]
      const slot = ball.body
      this.balls[slot] = undefined
      if (this.visible[slot] === 1) { this.visible[slot] = 0; this.visibleCount-- }
      if (ball.key.void) { this._discarded--; continue }
      onLanded(ball.key, ball, this.tick)
    }
  }

  /** Visible balls with what a late joiner needs to replay them from their seeds. */
  ballStates () {
    const world = this.simulator.world
    const states = []
    for (let slot = 0; slot < this.balls.length; slot++) {
      if (this.visible[slot] !== 1) continue
      states.push({ ...publicDropFacts(this.balls[slot]), x: world.xOf(slot), y: world.yOf(slot) })
    }
    return states
  }

  /** What GET /api/rooms lists. */
  summary () {
    return { id: this.id, rows: this.rows, risk: this.risk, players: this.clients.size, ballsInFlight: this.ballsInFlight, tick: this.tick }
  }
}
