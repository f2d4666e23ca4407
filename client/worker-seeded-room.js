/**
 * The page's side of a seeds-mode room simulated in the board worker
 * (board-worker-room.js): the same surface as SeededRoom (seeded-room.js)
 * for the rest of the page, with the simulation elsewhere. The page's
 * LocalDrops stay here; the worker gets a copy of each announced drop, the
 * room clock's line whenever it moves (the worker advances the render tick
 * on its own animation frames) and the desync checks, and reports what its
 * frames met: peg contacts and landings (played and shown here as the
 * report arrives, the worker having drawn their glows and pops), the drops
 * that left the board, and its counters. The render loop hears each report
 * (onReport) and runs no animation frame for the room itself.
 *
 * Money and verification do not depend on it: balances and results are
 * the server's, and a settled drop of the player's that the worker has not
 * landed yet is simulated here by the verifier (drop-verifier.js), by the
 * same engine, as a drop the page never drew is.
 */
import { firstSighting } from './seeded-room.js'

const MAX_TRACE = 50_000

export class WorkerSeededRoom {
  /**
   * @param {object} options
   * @param {string} options.room
   * @param {import('/engine/board.js').Board} options.board the room's board here (newest engine version the room runs)
   * @param {{ rows: number, risk: string }} options.boardOf
   * @param {import('./board-worker-client.js').WorkerBoard} options.worker
   * @param {import('./room-clock.js').RoomClock} options.clock the room's clock: its line goes to the worker as it moves
   */
  constructor ({ room, board, boardOf, worker, clock }) {
    this.room = room
    this.board = board
    this.worker = worker
    /** The worker poses and draws the balls on its own animation frames: the render loop asks for none meanwhile. */
    this.drawsInWorker = true
    /** @type {Map<number, import('./drop-verifier.js').LocalDrop>} on the board: announced, not yet faded out */
    this.drops = new Map()
    /** @type {{ bucket: number, mine: boolean, dropId: number, drop: import('./drop-verifier.js').LocalDrop, stale: boolean }[]} */
    this.landings = []
    /** @type {import('./room-view.js').PegHit[]} */
    this.pegHits = []
    this.unknownDrawn = 0
    /** The worker's SeededRoom counters, as of its last frame. */
    this.stats = { drops: 0, steps: 0, fastForwarded: 0, fastForwardSteps: 0, checks: 0, mismatches: 0, frames: 0, frameMs: 0 }
    /** Balls the worker drew in its last frame, and of them the player's. */
    this.balls = 0
    this.mineDrawn = 0
    this._seen = new Set()
    /** @type {{ dropId: number, tick: number, x: number, y: number }[] | null} */
    this._trace = null
    /** Hears each report, after this room took it in (the render loop: render-loop.js). @type {(report: import('./board-worker-room.js').DrivenReport) => void} */
    this.onReport = () => {}
    /** Called once, when the room is closed. */
    this.onClose = () => {}
    this.clock = clock
    worker.openSeedsRoom({ room, rows: boardOf.rows, risk: boardOf.risk, engineVersion: board.engineVersion }, (report) => this._report(report))
    clock.onChange = () => worker.seedsClock(clock.line)
    if (clock.line !== null) worker.seedsClock(clock.line)
  }

  /** Drawn positions (drop id, render tick, x, y), recorded in the worker while not null. */
  get trace () { return this._trace }
  set trace (value) {
    this._trace = value
    this.worker.seedsTrace(value !== null)
  }

  /** The player's own balls not landed on screen yet. */
  get ownInFlight () {
    let count = 0
    for (const drop of this.drops.values()) if (drop.mine && !drop.landingShown) count++
    return count
  }

  /** Whether this drop was put on the board (still there, or landed and gone). @param {number} dropId */
  has (dropId) {
    return this._seen.has(dropId)
  }

  /** Puts an announced drop's ball on the board (once per drop id). @param {import('./drop-verifier.js').LocalDrop} drop */
  add (drop) {
    if (!firstSighting(this._seen, drop.dropId)) return
    this.drops.set(drop.dropId, drop)
    this.stats.drops++
    const { dropId, dropSeed, engineVersion, startTick, slot, mine, player, bet } = drop
    this.worker.seedsAdd({ dropId, dropSeed, engineVersion, startTick, slot, mine, player, bet })
  }

  /** Its settlement came: the worker steps the ball to its landing (the drawing still follows the clock). @param {number} dropId */
  complete (dropId) {
    this.worker.seedsComplete(dropId)
  }

  /**
   * The desync check, in the worker.
   * @param {number} tick @param {string} hash
   * @returns {Promise<{ ok: boolean, tick: number, server: string, local: string, balls: number } | null>} null: the room was left meanwhile
   */
  check (tick, hash) {
    // Counted here as answered (the worker's reports come only while it draws).
    return this.worker.seedsCheck(tick, hash).then((result) => {
      if (result) {
        this.stats.checks++
        if (!result.ok) this.stats.mismatches++
      }
      return result
    })
  }

  /** Another room (or delivery) replaces this one: the worker stops simulating it. */
  close () {
    this.clock.onChange = () => {}
    this.worker.closeSeedsRoom()
    const onClose = this.onClose
    this.onClose = () => {}
    onClose()
  }

  /** @param {import('./board-worker-room.js').DrivenReport} report */
  _report (report) {
    this.balls = report.balls
    this.mineDrawn = report.mine
    // Drops are counted here as they are put on the board (the worker's count trails by the messages on their way),
    // and checks as they are answered.
    const { drops, checks, mismatches, ...counters } = report.stats
    Object.assign(this.stats, counters)
    for (const hit of report.pegHits) this.pegHits.push(hit)
    for (const landing of report.landings) {
      const drop = this.drops.get(landing.dropId)
      if (!drop) continue
      if (drop.ticks === null) Object.assign(drop, { bucket: landing.bucket, ticks: landing.ticks, stateHash: landing.stateHash })
      if (!drop.mine && landing.result) drop.result = landing.result
      // Not landingShown yet: that is when the render loop plays it (onReport; a `settled` coming
      // before it must wait for it, or its payout would not float).
      this.landings.push({ bucket: landing.bucket, mine: drop.mine, dropId: drop.dropId, drop, stale: landing.stale })
    }
    for (const dropId of report.retired) this.drops.delete(dropId)
    if (this._trace && report.trace) {
      for (const point of report.trace) if (this._trace.length < MAX_TRACE) this._trace.push(point)
    }
    this.onReport(report)
  }
}
