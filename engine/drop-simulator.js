import { World } from './world.js'
import { bucketAt } from './board.js'
import { dropInitialConditions } from './drop-initial-conditions.js'
import { assertSolver } from './solver.js'
/**
 * Static-grid cells (px) for boards, as a multiple of the ball's radius:
 * cells that small keep the pegs a ball must test per sub-step to about
 * two, on every board's scale (the world's default is 50 px). Any size
 * gives the same outcomes: a cell lists every shape its balls can reach.
 */
export const STATIC_CELLS_PER_BALL_RADIUS = 1

/**
 * @typedef {object} DropOutcome
 * @property {number} bucket @property {number} multiplier
 * @property {number} ticks steps from release to landing
 * @property {string} stateHash hash of the ball's exact state when it landed
 */

/**
 * @typedef {DropOutcome & { key: any, body: number, x: number, y: number, angle: number }} LandedDrop
 */

/**
 * A board's world with any number of balls in flight. Balls do not collide
 * with each other, so each ball's path depends on its drop seed and the
 * board alone: a drop replayed by itself lands exactly as it did in a busy
 * room. Used by the server's rooms, the browser's replay and simulateDrop.
 */
export class DropSimulator {
  /** @param {import('./board.js').Board} board */
  constructor (board) {
    this.board = board
    const statics = boardStatics(board)
    this.world = new World({ gravityY: statics.gravityY, timestep: statics.timestep, maxBodyRadius: board.ballRadius, sharedStatics: statics })
    // Per body id: the caller's key and ticks since release (-1: not a drop).
    this._keys = []
    this._ticks = new Int32Array(64).fill(-1)
    this._inFlight = 0
    // The version's tick cap: a ball still in play after this many ticks
    // lands where it is, so a wedged ball can never hang a replay.
    this._maxTicks = board.maxDropTicks
    /** @type {LandedDrop[]} drops that landed in the last step, in body-id order */
    this.landed = []
  }

  /**
   * Releases a ball for `dropSeed`. Returns its body id.
   * @param {string} dropSeed @param {any} [key] caller's handle, echoed on landing
   */
  addDrop (dropSeed, key = dropSeed) {
    const start = dropInitialConditions(this.board, dropSeed)
    start.radius = this.board.ballRadius
    start.material = this.board.ballMaterial
    start.collidesWithBodies = false
    const body = this.world.createCircle(start)
    if (body >= this._ticks.length) {
      const grown = new Int32Array(this._ticks.length * 2).fill(-1)
      grown.set(this._ticks)
      this._ticks = grown
    }
    this._keys[body] = key
    this._ticks[body] = 0
    this._inFlight++
    return body
  }

  get inFlight () { return this._inFlight }

  /**
   * Ticks since release of the drop on body `body`, or -1.
   * @param {number} body
   */
  ticksOf (body) {
    return body < this._ticks.length ? this._ticks[body] : -1
  }

  /** Advances one tick; returns `landed`: the balls that landed in it, in body-id order. */
  step () {
    this.world.step()
    if (this.landed.length !== 0) this.landed.length = 0
    const world = this.world
    const ticks = this._ticks
    const lineY = this.board.bucketLineY
    const maxTicks = this._maxTicks
    for (let id = 0, count = world.bodyCount; id < count; id++) {
      if (ticks[id] < 0) continue
      const age = ++ticks[id]
      if (world.yOf(id) > lineY || age >= maxTicks) this._land(id, age)
    }
    return this.landed
  }

  _land (id, age) {
    const world = this.world
    const bucket = bucketAt(this.board, world.xOf(id))
    this.landed.push({
      key: this._keys[id],
      body: id,
      bucket,
      multiplier: this.board.multipliers[bucket],
      ticks: age,
      stateHash: world.bodyStateHash(id),
      x: world.xOf(id),
      y: world.yOf(id),
      angle: world.angleOf(id)
    })
    this._keys[id] = undefined
    this._ticks[id] = -1
    this._inFlight--
    world.destroyBody(id)
  }
}

/** board → a world holding only its pegs and walls, shared by every DropSimulator on that board */
const staticWorlds = new WeakMap()

/** @param {import('./board.js').Board} board */
function boardStatics (board) {
  let world = staticWorlds.get(board)
  if (!world) {
    assertSolver(board.solver, board.engineVersion)
    const { gravity, timestep } = board.solver
    world = new World({ gravityY: gravity, timestep, maxBodyRadius: board.ballRadius, staticCellSize: board.ballRadius * STATIC_CELLS_PER_BALL_RADIUS, capacity: 1 })
    const material = board.pegMaterial
    for (const peg of board.pegs) world.addStaticCircle(peg.x, peg.y, board.pegRadius, material)
    for (const [x1, y1, x2, y2] of board.walls) world.addStaticSegment(x1, y1, x2, y2, material)
    staticWorlds.set(board, world)
  }
  return world
}

const simulators = new WeakMap()

/**
 * Simulates one drop from its seed to landing.
 * @param {import('./board.js').Board} board
 * @param {string} dropSeed
 * @param {{ trajectory?: boolean }} [options] trajectory: also return x, y, angle after every tick
 * @returns {DropOutcome & { trajectory?: Float64Array }}
 */
export function simulateDrop (board, dropSeed, options = {}) {
  let simulator = simulators.get(board)
  if (!simulator) simulators.set(board, (simulator = new DropSimulator(board)))
  if (simulator.inFlight !== 0) simulator = new DropSimulator(board) // re-entrant use
  const body = simulator.addDrop(dropSeed)
  const world = simulator.world
  const path = options.trajectory ? [world.xOf(body), world.yOf(body), world.angleOf(body)] : null
  for (;;) {
    const landed = simulator.step()
    if (landed.length > 0) {
      const { bucket, multiplier, ticks, stateHash, x, y, angle } = landed[0]
      if (!path) return { bucket, multiplier, ticks, stateHash }
      path.push(x, y, angle)
      return { bucket, multiplier, ticks, stateHash, trajectory: Float64Array.from(path) }
    }
    if (path) path.push(world.xOf(body), world.yOf(body), world.angleOf(body))
  }
}
