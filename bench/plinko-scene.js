/**
 * The benchmark scene, defined once and built three ways (scene-ours.js,
 * scene-matter.js, scene-planck.js): a Plinko board from createBoard() with
 * static pegs and walls, and dynamic balls that do not collide with each
 * other, released from the drop zone at staggered times and respawned at the
 * top as soon as they pass the bucket line, so `balls` are always in flight.
 *
 * Every engine gets the same start conditions (position, velocity, angle,
 * spin), drawn by the engine's own dropInitialConditions() from drop seeds
 * derived as in production (HMAC-SHA256), in the same order.
 */
import { createBoard, dropInitialConditions, engineRules, ENGINE_VERSION } from '../engine/index.js'
import { dropSeedSync } from '../cli/drop-seeds.js'

export const SCENE = Object.freeze({
  /** the board, materials and tick limit of the newest engine version */
  engineVersion: ENGINE_VERSION,
  rows: 16,
  risk: 'medium',
  /** balls in flight once all are released */
  balls: 100,
  /** ticks between two first releases (the ramp is over after balls × releaseEvery ticks) */
  releaseEvery: 3,
  /** seconds per step, in every engine */
  timestep: 1 / 60,
  /** px/s², downwards */
  gravity: 980,
  /** a ball still in flight after this many ticks is respawned, as DropSimulator lands it */
  maxTicks: engineRules(ENGINE_VERSION).maxDropTicks,
  /** planck works in metres: 1 m = 100 px, so the ball is 0.07 m and gravity 9.8 m/s² */
  pixelsPerMetre: 100
})

/** Materials of the scene's engine version; the peers get the same values (see the scene files for how each mixes them). */
export const BALL_MATERIAL = engineRules(ENGINE_VERSION).ballMaterial
export const PEG_MATERIAL = engineRules(ENGINE_VERSION).pegMaterial

export const BENCH_SERVER_SEED = 'plinko-bench-server-seed'
export const BENCH_CLIENT_SEED = 'plinko-bench-client-seed'

/**
 * Drop seeds for nonces first..first+count-1, derived as the server does.
 * @param {number} count @param {number} [first]
 * @returns {string[]}
 */
export function benchDropSeeds (count, first = 0) {
  const seeds = new Array(count)
  for (let i = 0; i < count; i++) seeds[i] = dropSeedSync(BENCH_SERVER_SEED, BENCH_CLIENT_SEED, first + i)
  return seeds
}

/** Floats per start in a start table: x, y (px), vx, vy (px/s), angle (rad), angular velocity (rad/s). */
export const START_STRIDE = 6

/**
 * Start conditions of the given drop seeds, flat: START_STRIDE floats each.
 * @param {import('../engine/board.js').Board} board @param {string[]} seeds
 */
export function startTable (board, seeds) {
  const table = new Float64Array(seeds.length * START_STRIDE)
  seeds.forEach((seed, k) => {
    const s = dropInitialConditions(board, seed)
    table.set([s.x, s.y, s.vx, s.vy, s.angle, s.angularVelocity], k * START_STRIDE)
  })
  return table
}

/** @param {number} [rows] @param {string} [engineVersion] */
export function sceneBoard (rows = SCENE.rows, engineVersion = SCENE.engineVersion) {
  return createBoard({ rows, risk: SCENE.risk, engineVersion })
}

/**
 * Shared bookkeeping of every engine's scene: when the next ball is due,
 * which start comes next (cycling through the table), each ball's age, and
 * how many drops completed. The engine-specific scene owns the bodies.
 */
export class BallSchedule {
  /**
   * @param {Float64Array} starts start table
   * @param {number} balls @param {number} releaseEvery
   */
  constructor (starts, balls, releaseEvery) {
    this.starts = starts
    this.startCount = starts.length / START_STRIDE
    this.balls = balls
    this.releaseEvery = releaseEvery
    this.nextStart = 0
    this.released = 0
    this.tick = 0
    this.ages = new Int32Array(balls)
    /** drops that reached the bucket line (or maxTicks) */
    this.landed = 0
    /** sum of the ticks of those drops */
    this.landedTicks = 0
  }

  /** Whether a new ball is due before this tick's step. */
  releaseDue () {
    return this.released < this.balls && this.tick % this.releaseEvery === 0
  }

  /** Index of the next start (its floats begin at index × START_STRIDE); advances the cycle. */
  takeStart () {
    const index = this.nextStart
    this.nextStart = index + 1 === this.startCount ? 0 : index + 1
    return index
  }

  /**
   * Ages ball k by one tick; returns true when it has landed (centre below
   * the bucket line, or maxTicks reached), counting the drop.
   * @param {number} k @param {number} y px @param {number} lineY px
   */
  ageAndCheck (k, y, lineY) {
    const age = ++this.ages[k]
    if (y <= lineY && age < SCENE.maxTicks) return false
    this.landed++
    this.landedTicks += age
    this.ages[k] = 0
    return true
  }
}
