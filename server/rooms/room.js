import { DropSimulator, BODY_STRIDE, BODY_X, BODY_Y } from '../../engine/index.js'
import { encodeSnapshot, encodeRoomFrame } from '../../protocol/snapshot-codec.js'
import { publicDropFacts } from '../game/drop.js'

/**
 * One board, its simulator and the connections watching it. Lifecycle:
 * created on the first join, stepped by the arena's scheduler, disposed by
 * the registry once it has no clients and no balls in flight.
 *
 * A ball's slot is its body id in the simulator: small, reused lowest first
 * once the ball has landed. A ball is *visible* (in snapshots and in
 * `joined`) only after its drop has been recorded and announced, so every
 * slot a client sees has been named in a `dropped` message first.
 */
export class Room {
  /**
   * @param {object} options
   * @param {string} options.id
   * @param {import('../../engine/board.js').Board} options.board
   * @param {number} options.snapshotEvery ticks between snapshots
   * @param {number} [options.snapshotPhase] offset so rooms' snapshots fall on different ticks
   */
  constructor ({ id, board, snapshotEvery, snapshotPhase = 0 }) {
    this.id = id
    this.board = board
    this.rows = board.rows
    this.risk = board.risk
    this.simulator = new DropSimulator(board)
    /** Ticks stepped since the room was created. A ball released at tick T lands at T + ticks. */
    this.tick = 0
    this.snapshotEvery = snapshotEvery
    this.snapshotPhase = snapshotPhase % snapshotEvery
    /** @type {Set<import('../realtime/connection.js').Connection>} */
    this.clients = new Set()
    /** @type {(import('../game/drop.js').Drop | undefined)[]} drop by slot, while in flight */
    this.balls = []
    this.visible = new Uint8Array(64)
    this.visibleCount = 0
    this._lastSnapshotHadBalls = false
    this._discarded = 0
    /** `dropped`/`settled` (JSON text) for the room's clients, sent with the next snapshot. */
    this.pendingEvents = []
  }

  /** Queues an event for everyone in the room; it goes out with the next snapshot (or before a join). @param {string} text */
  queueEvent (text) {
    if (this.clients.size > 0) this.pendingEvents.push(text)
  }

  /** The `events` message (JSON text) carrying `events`, a JSON array from takeEvents(). @param {string} events */
  eventsMessage (events) {
    return `{"type":"events","room":${JSON.stringify(this.id)},"events":${events}}`
  }

  /** Sends `events` (from takeEvents()) to the room's clients as an `events` message, with no snapshot. @param {string} events */
  sendEvents (events) {
    const text = this.eventsMessage(events)
    for (const client of this.clients) client.sendEvent(text, 'events')
  }

  /** Sends the queued events now, without waiting for the next snapshot. */
  sendQueuedEvents () {
    const events = this.takeEvents()
    if (events !== null) this.sendEvents(events)
  }

  /** The queued events as one JSON array text, or null if none; clears the queue. */
  takeEvents () {
    if (this.pendingEvents.length === 0) return null
    const json = `[${this.pendingEvents.join(',')}]`
    this.pendingEvents.length = 0
    return json
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

  get snapshotDue () {
    return (this.tick + this.snapshotPhase) % this.snapshotEvery === 0
  }

  /**
   * What the room's clients get this snapshot period: `frame` (binary: the
   * queued events, if any, and the snapshot) and `events` (the queued events
   * as JSON text, or null), which a client that must skip the snapshot still
   * gets. Both null when there is nothing to say.
   * @returns {{ frame: Buffer | null, events: string | null }}
   */
  encodeFrame () {
    const events = this.takeEvents()
    const snapshot = this.encodeSnapshot()
    if (snapshot === null) return { frame: null, events }
    return { frame: events === null ? snapshot : encodeRoomFrame(events, snapshot), events }
  }

  /**
   * The snapshot frame for the current tick, or null when there is nothing
   * new to say (no balls now and none in the previous frame).
   */
  encodeSnapshot () {
    if (this.visibleCount === 0 && !this._lastSnapshotHadBalls) return null
    this._lastSnapshotHadBalls = this.visibleCount > 0
    const world = this.simulator.world
    return encodeSnapshot(this.tick, this.visible, world.bodyCount, world.state, world.state, BODY_STRIDE, BODY_X, BODY_Y)
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
