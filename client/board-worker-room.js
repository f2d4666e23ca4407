import { SeededRoom } from './seeded-room.js'
import { BoardCache } from './board-cache.js'
import { packPoses, poseBuffer, STRIDE } from './pose-frame.js'

/**
 * The joined room's seeds-mode simulation, run in the board worker
 * (board-worker.js) beside the painter: the page's main thread sends the
 * announced drops and, each animation frame, the render tick from its room
 * clock; here every ball is stepped and posed (seeded-room.js, the same
 * code as on the main thread) and packed for the painter, so the
 * simulation, the poses and their hand-over leave the main thread. What
 * the page needs back rides in each frame's answer (a FrameReport): the
 * peg contacts and landings the drawing met (sound, effects, the results
 * shown as balls land), the drops that left the board, the balls drawn and
 * the simulation's counters; the desync check is answered on its own.
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
    const landings = view.landings.map(({ dropId, bucket, stale, drop }) => ({ dropId, bucket, stale, ticks: drop.ticks, stateHash: drop.stateHash, result: drop.result ?? null }))
    /** @type {FrameReport} */
    const report = { balls: count, mine, pegHits: view.pegHits, landings, retired: view.retired, stats: { ...view.stats }, trace: view.trace }
    view.pegHits = []
    view.landings = []
    view.retired = []
    if (view.trace) view.trace = []
    return { poses: this._poses, count, report }
  }
}

/**
 * An announced drop as the worker gets it (the page's LocalDrop, less what it does not need).
 * @typedef {{ dropId: number, dropSeed: string, engineVersion: string, startTick: number, slot: number, mine: boolean, player: string, bet?: number }} WorkerDrop
 */

/**
 * @typedef {object} FrameReport
 * @property {number} balls drawn @property {number} mine of them the player's
 * @property {import('./room-view.js').PegHit[]} pegHits
 * @property {{ dropId: number, bucket: number, stale: boolean, ticks: number, stateHash: string, result: object | null }[]} landings
 * @property {number[]} retired drop ids that left the board
 * @property {object} stats SeededRoom.stats
 * @property {{ dropId: number, tick: number, x: number, y: number }[] | null} trace drawn positions since the last report, when tracing
 */
