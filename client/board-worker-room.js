import { SeededRoom } from './seeded-room.js'
import { BoardCache } from './board-cache.js'
import { packPoses, poseBuffer, STRIDE } from './pose-frame.js'
import { RenderTickFollower } from './room-clock.js'

/** A report goes to the page at least this often while frames are drawn (its counters), else only with events. */
export const REPORT_EVERY_MS = 250

/**
 * The joined room's seeds-mode simulation, run in the board worker
 * (board-worker.js) beside the painter: the page's main thread sends the
 * announced drops and its room clock's line; here every ball is stepped
 * and posed (seeded-room.js, the same code as on the main thread) and
 * packed for the painter, so the simulation, the poses and their
 * hand-over leave the main thread. What the page needs back rides in a
 * frame's report (a FrameReport): the
 * peg contacts and landings the drawing met (sound, effects, the results
 * shown as balls land), the drops that left the board, the balls drawn and
 * the simulation's counters; the desync check is answered on its own.
 *
 * The worker draws the room's frames on its own animation frames
 * (drive(), board-worker.js): the page sends the room clock's line
 * (room-clock.js) when it moves, the render tick is advanced here, the
 * peg glows and bucket pops of what the simulation met are started here,
 * and the page hears a report only when something happened that it plays
 * (a sound, a landing, a ball gone) or every REPORT_EVERY_MS. The page's
 * main thread then runs no animation frame of its own for the room: in
 * Chromium an animation frame costs the main thread its rendering
 * lifecycle even when it changes nothing (about 1.9 ms a frame on an idle
 * page under 4× CPU throttling, against 0.1 ms without; docs/client.md).
 */
export class WorkerRoom {
  /**
   * @param {{ room: string, rows: number, risk: string, engineVersion: string }} spec the room and its board under its newest engine version
   */
  constructor ({ room, rows, risk, engineVersion }) {
    const boards = new BoardCache()
    this.view = new SeededRoom({ room, board: boards.board(rows, risk, engineVersion), boardFor: (version) => boards.board(rows, risk, version) })
    this.view.retired = []
    this._poses = poseBuffer(0)
    /** The room clock's line (room-clock.js ClockLine), null until the page's clock has one. */
    this.line = null
    this.follower = new RenderTickFollower()
    /** What the page has not heard yet (drive()). */
    this._unreported = emptyUnreported()
    this._reportedAt = -Infinity
    /** The last frame drawn showed nothing moving (the next such frame is skipped). */
    this._stillDrawn = false
  }

  /**
   * One of the worker's animation frames at page time `now`: advances the
   * render tick, starts the effects of what the simulation met (none with
   * reduced motion), draws unless nothing moves and the last frame already
   * showed that, and returns the report due to the page (null: none due).
   * @param {import('./board-painter.js').BoardPainter} painter
   * @param {number} now ms, page time
   * @param {{ reducedMotion: boolean, changed: boolean }} options changed: something besides the balls was changed since the last frame (a layout, an effect)
   * @returns {{ report: DrivenReport | null, moving: boolean }} moving: the next frame is needed
   */
  drive (painter, now, options) {
    return this.drawFrame(painter, this.follower.advance(this.line, now), now, options)
  }

  /**
   * drive() at render tick `tick` (null: no clock line yet).
   * @param {import('./board-painter.js').BoardPainter} painter @param {number | null} tick @param {number} now
   * @param {{ reducedMotion: boolean, changed: boolean }} options
   * @returns {{ report: DrivenReport | null, moving: boolean }}
   */
  drawFrame (painter, tick, now, { reducedMotion, changed }) {
    const { poses, count, report } = this.frame(tick)
    const due = this._unreported
    for (const hit of report.pegHits) {
      if (reducedMotion) continue
      painter.apply(['glow', hit.peg, hit.mine, now])
      due.pegGlows++
    }
    for (const landing of report.landings) {
      if (reducedMotion || landing.stale) continue
      painter.apply(['flash', landing.bucket, landing.mine, now])
      due.bucketPops++
    }
    const moving = count > 0 || this.view.drops.size > 0
    const still = !moving && !changed && !painter.animating
    if (!(still && this._stillDrawn)) {
      const stats = painter.draw({ poses, count, now, reducedMotion })
      if (stats) {
        due.frames++
        due.trails += stats.trails
        if (stats.floaterClearance !== null) due.floaterClearance = Math.min(due.floaterClearance ?? Infinity, stats.floaterClearance)
      }
    }
    this._stillDrawn = still
    for (const hit of report.pegHits) due.pegHits.push(hit)
    for (const landing of report.landings) due.landings.push(landing)
    for (const dropId of report.retired) due.retired.push(dropId)
    if (report.trace) for (const point of report.trace) due.trace.push(point)
    const next = moving || painter.animating
    const events = due.pegHits.length + due.landings.length + due.retired.length + due.trace.length > 0
    // The last frame before the frames stop reports too: the page's counters stay current.
    const countersDue = due.frames > 0 && (now - this._reportedAt >= REPORT_EVERY_MS || !next)
    if (!events && !countersDue) return { report: null, moving: next }
    this._unreported = emptyUnreported()
    this._reportedAt = now
    const { frames, trails, floaterClearance, pegGlows, bucketPops } = due
    /** @type {DrivenReport} */
    const driven = { ...report, pegHits: due.pegHits, landings: due.landings, retired: due.retired, trace: report.trace ? due.trace : null, drawn: { frames, trails, floaterClearance, pegGlows, bucketPops } }
    return { report: driven, moving: next }
  }

  /** @param {WorkerDrop} drop */
  add (drop) { this.view.add(drop) }

  /** @param {number} dropId */
  complete (dropId) { this.view.complete(dropId) }

  /** The desync check (SeededRoom.check). @param {number} tick @param {string} hash */
  check (tick, hash) { return this.view.check(tick, hash) }

  /** Starts (or stops) recording the drawn positions; they ride in the frame reports. @param {boolean} on */
  trace (on) { this.view.trace = on ? [] : null }

  /**
   * The balls at render tick `tick` (null: the clock has no sample yet),
   * packed for the painter, and what the page hears of the frame.
   * @param {number | null} tick
   * @returns {{ poses: Float64Array, count: number, report: FrameReport }}
   */
  frame (tick) {
    const view = this.view
    const poses = tick === null ? [] : view.posesAt(tick)
    if (this._poses.length < poses.length * STRIDE) this._poses = poseBuffer(poses.length)
    const count = packPoses(poses, this._poses)
    let mine = 0
    for (const pose of poses) if (pose.mine) mine++
    const landings = view.landings.map(({ dropId, bucket, stale, drop }) => ({ dropId, bucket, mine: drop.mine, stale, ticks: drop.ticks, stateHash: drop.stateHash, result: drop.result ?? null }))
    /** @type {FrameReport} */
    const report = { balls: count, mine, pegHits: view.pegHits, landings, retired: view.retired, stats: { ...view.stats }, trace: view.trace }
    view.pegHits = []
    view.landings = []
    view.retired = []
    if (view.trace) view.trace = []
    return { poses: this._poses, count, report }
  }
}

function emptyUnreported () {
  return { pegHits: [], landings: [], retired: [], trace: [], frames: 0, trails: 0, floaterClearance: null, pegGlows: 0, bucketPops: 0 }
}

/**
 * A FrameReport of the frames the worker drew on its own since the last
 * report (drive()): their events together, the counters of the last, and
 * what was drawn.
 * @typedef {FrameReport & { drawn: { frames: number, trails: number, floaterClearance: number | null, pegGlows: number, bucketPops: number } }} DrivenReport
 */

/**
 * An announced drop as the worker gets it (the page's LocalDrop, less what it does not need).
 * @typedef {{ dropId: number, dropSeed: string, engineVersion: string, startTick: number, slot: number, mine: boolean, player: string, bet?: number }} WorkerDrop
 */

/**
 * @typedef {object} FrameReport
 * @property {number} balls drawn @property {number} mine of them the player's
 * @property {import('./room-view.js').PegHit[]} pegHits
 * @property {{ dropId: number, bucket: number, mine: boolean, stale: boolean, ticks: number, stateHash: string, result: object | null }[]} landings
 * @property {number[]} retired drop ids that left the board
 * @property {object} stats SeededRoom.stats
 * @property {{ dropId: number, tick: number, x: number, y: number }[] | null} trace drawn positions since the last report, when tracing
 */
