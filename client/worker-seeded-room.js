/**
 * The page's side of a seeds-mode room simulated in the board worker
 * (board-worker-room.js): the same surface as SeededRoom (seeded-room.js)
 * for the rest of the page, with the simulation elsewhere. The page's
 * LocalDrops stay here; the worker gets a copy of each announced drop, the
 * render tick with each frame (board-worker-client.js seedsFrame) and the
 * desync checks, and answers each drawn frame with what the drawing met:
 * peg contacts and landings (played and shown here a frame later than the
 * worker drew them), the drops that left the board, and its counters.
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
   */
  constructor ({ room, board, boardOf, worker }) {
    this.room = room
    this.board = board
    this.worker = worker
    /** The worker poses and draws the balls: the render loop sends it the tick only. */
    this.drawsInWorker = true
    /** @type {Map<number, import('./drop-verifier.js').LocalDrop>} on the board: announced, not yet faded out */
    this.drops = new Map()
    /** @type {{ bucket: number, mine: boolean, dropId: number, drop: import('./drop-verifier.js').LocalDrop, stale: boolean }[]} */
    this.landings = []
    /** @type {import('./room-view.js').PegHit[]} */
    this.pegHits = []
    this.unknownDrawn = 0
    this.lastTick = null
    /** The worker's SeededRoom counters, as of its last frame. */
    this.stats = { drops: 0, steps: 0, fastForwarded: 0, fastForwardSteps: 0, checks: 0, mismatches: 0, frames: 0, frameMs: 0 }
    /** Balls the worker drew in its last frame, and of them the player's. */
    this.balls = 0
    this.mineDrawn = 0
    this._seen = new Set()
    /** @type {{ dropId: number, tick: number, x: number, y: number }[] | null} */
    this._trace = null
    worker.openSeedsRoom({ room, rows: boardOf.rows, risk: boardOf.risk, engineVersion: board.engineVersion }, (report) => this._report(report))
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
    return this.worker.seedsCheck(tick, hash)
  }

  /** Another room (or delivery) replaces this one: the worker stops simulating it. */
  close () {
    this.worker.closeSeedsRoom()
  }

  /** @param {import('./board-worker-room.js').FrameReport} report */
  _report (report) {
    this.balls = report.balls
    this.mineDrawn = report.mine
    // Drops are counted here as they are put on the board (the worker's count trails by the messages on their way).
    const { drops, ...counters } = report.stats
    Object.assign(this.stats, counters)
    for (const hit of report.pegHits) this.pegHits.push(hit)
    for (const landing of report.landings) {
      const drop = this.drops.get(landing.dropId)
      if (!drop) continue
      if (drop.ticks === null) Object.assign(drop, { bucket: landing.bucket, ticks: landing.ticks, stateHash: landing.stateHash })
      if (!drop.mine && landing.result) drop.result = landing.result
      // Not landingShown yet: that is when the render loop plays it, next frame (a `settled` coming
      // in between must wait for it, or its payout would not float).
      this.landings.push({ bucket: landing.bucket, mine: drop.mine, dropId: drop.dropId, drop, stale: landing.stale })
    }
    for (const dropId of report.retired) this.drops.delete(dropId)
    if (this._trace && report.trace) {
      for (const point of report.trace) if (this._trace.length < MAX_TRACE) this._trace.push(point)
    }
  }
}
