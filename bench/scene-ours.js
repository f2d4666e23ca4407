/**
 * The benchmark scene in our engine, two ways:
 * - OursScene: the world exactly as DropSimulator builds it (same static
 *   grid, same materials, balls with collidesWithBodies: false), stepped
 *   with World.step(); a landed ball is destroyed and a new one created from
 *   the next start, the engine's own way to reuse a body. This is the
 *   like-for-like peer of the matter-js and planck scenes.
 * - OursServerScene: the server's path, DropSimulator.addDrop(seed) and
 *   DropSimulator.step(), which also draws the start from the seed
 *   (seedrandom) and records every landing (bucket, state hash).
 */
import { DropSimulator } from '../engine/index.js'
import { SCENE, BALL_MATERIAL, BallSchedule, START_STRIDE } from './plinko-scene.js'

export class OursScene {
  /**
   * @param {import('../engine/board.js').Board} board
   * @param {Float64Array} starts start table (plinko-scene.js)
   * @param {{ balls?: number, releaseEvery?: number }} [options]
   */
  constructor (board, starts, { balls = SCENE.balls, releaseEvery = SCENE.releaseEvery } = {}) {
    this.lineY = board.bucketLineY
    this.world = new DropSimulator(board).world
    this.schedule = new BallSchedule(starts, balls, releaseEvery)
    this.ids = new Int32Array(balls)
    // createCircle() reads a definition object: one per start, built here, so the scene itself allocates nothing on a respawn.
    this.definitions = []
    for (let offset = 0; offset < starts.length; offset += START_STRIDE) {
      this.definitions.push({
        x: starts[offset],
        y: starts[offset + 1],
        vx: starts[offset + 2],
        vy: starts[offset + 3],
        angle: starts[offset + 4],
        angularVelocity: starts[offset + 5],
        radius: board.ballRadius,
        material: BALL_MATERIAL,
        collidesWithBodies: false
      })
    }
  }

  step () {
    const schedule = this.schedule
    const world = this.world
    if (schedule.releaseDue()) this.ids[schedule.released++] = this._create()
    world.step()
    schedule.tick++
    const ids = this.ids
    for (let k = 0, n = schedule.released; k < n; k++) {
      if (schedule.ageAndCheck(k, world.yOf(ids[k]), this.lineY)) {
        world.destroyBody(ids[k])
        ids[k] = this._create()
      }
    }
  }

  /** drops completed so far */
  get landed () { return this.schedule.landed }
  /** sum of their ticks */
  get landedTicks () { return this.schedule.landedTicks }

  _create () {
    return this.world.createCircle(this.definitions[this.schedule.takeStart()])
  }
}

export class OursServerScene {
  /**
   * @param {import('../engine/board.js').Board} board
   * @param {string[]} seeds drop seeds, used in turn (cycling)
   * @param {{ balls?: number, releaseEvery?: number }} [options]
   */
  constructor (board, seeds, { balls = SCENE.balls, releaseEvery = SCENE.releaseEvery } = {}) {
    this.simulator = new DropSimulator(board)
    this.seeds = seeds
    this.nextSeed = 0
    this.balls = balls
    this.releaseEvery = releaseEvery
    this.released = 0
    this.tick = 0
    this.landed = 0
    this.landedTicks = 0
  }

  step () {
    if (this.released < this.balls && this.tick % this.releaseEvery === 0) {
      this.released++
      this._drop()
    }
    const landed = this.simulator.step()
    this.tick++
    for (let k = 0; k < landed.length; k++) {
      this.landed++
      this.landedTicks += landed[k].ticks
      this._drop()
    }
  }

  _drop () {
    this.simulator.addDrop(this.seeds[this.nextSeed])
    this.nextSeed = this.nextSeed + 1 === this.seeds.length ? 0 : this.nextSeed + 1
  }
}
