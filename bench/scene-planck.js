/**
 * The benchmark scene in planck, in metres: 1 m = SCENE.pixelsPerMetre px
 * (100), so the board is about 6.6 m wide, a ball 0.07 m in radius and
 * gravity 9.8 m/s², with y pointing down as in the board's pixels.
 * - One static ground body holds the pegs (circle fixtures) and the walls
 *   (edge fixtures, the board's segments).
 * - Balls: dynamic bodies with one circle fixture, filterGroupIndex -1, so
 *   balls never collide with each other.
 * - Materials: planck mixes restitution by max and friction by geometric
 *   mean, as our engine does, so fixtures get our materials as they are.
 *   Settings.velocityThreshold (below it a contact is inelastic) is set to
 *   0.3 m/s = 30 px/s, our engine's RESTITUTION_THRESHOLD.
 * - Step: world.step(1/60, 8, 3), planck's default iterations; continuous
 *   collision against static bodies is on, as by default. A landed ball is
 *   moved back to the top with setTransform/setLinearVelocity/setAngularVelocity.
 */
import { World, Circle, Edge, Vec2, Settings } from 'planck'
import { RESTITUTION_THRESHOLD } from '../engine/contact-solver.js'
import { SCENE, BALL_MATERIAL, PEG_MATERIAL, BallSchedule, START_STRIDE } from './plinko-scene.js'

export const PLANCK_VELOCITY_ITERATIONS = 8
export const PLANCK_POSITION_ITERATIONS = 3
const SCALE = 1 / SCENE.pixelsPerMetre

export class PlanckScene {
  /**
   * @param {import('../engine/board.js').Board} board
   * @param {Float64Array} starts start table (plinko-scene.js)
   * @param {{ balls?: number, releaseEvery?: number, continuousPhysics?: boolean }} [options]
   *   continuousPhysics: planck's default true; false only for the reference
   *   row that shows what time of impact costs (without it balls may tunnel)
   */
  constructor (board, starts, { balls = SCENE.balls, releaseEvery = SCENE.releaseEvery, continuousPhysics = true } = {}) {
    Settings.velocityThreshold = RESTITUTION_THRESHOLD * SCALE
    this.lineY = board.bucketLineY * SCALE
    this.schedule = new BallSchedule(starts, balls, releaseEvery)
    const world = new World({ gravity: new Vec2(0, SCENE.gravity * SCALE), continuousPhysics })
    this.world = world
    const ground = world.createBody()
    const plastic = { friction: PEG_MATERIAL.friction, restitution: PEG_MATERIAL.restitution }
    for (const peg of board.pegs) {
      ground.createFixture(new Circle(new Vec2(peg.x * SCALE, peg.y * SCALE), board.pegRadius * SCALE), plastic)
    }
    for (const [x1, y1, x2, y2] of board.walls) {
      ground.createFixture(new Edge(new Vec2(x1 * SCALE, y1 * SCALE), new Vec2(x2 * SCALE, y2 * SCALE)), plastic)
    }
    this.ballShape = new Circle(board.ballRadius * SCALE)
    this.balls = []
    this._point = new Vec2(0, 0)
  }

  step () {
    const schedule = this.schedule
    if (schedule.releaseDue()) {
      schedule.released++
      const ball = this.world.createBody({ type: 'dynamic' })
      ball.createFixture(this.ballShape, {
        density: BALL_MATERIAL.density,
        friction: BALL_MATERIAL.friction,
        restitution: BALL_MATERIAL.restitution,
        filterGroupIndex: -1
      })
      this._place(ball)
      this.balls.push(ball)
    }
    this.world.step(SCENE.timestep, PLANCK_VELOCITY_ITERATIONS, PLANCK_POSITION_ITERATIONS)
    schedule.tick++
    const balls = this.balls
    for (let k = 0, n = balls.length; k < n; k++) {
      if (schedule.ageAndCheck(k, balls[k].getPosition().y, this.lineY)) this._place(balls[k])
    }
  }

  get landed () { return this.schedule.landed }
  get landedTicks () { return this.schedule.landedTicks }

  _place (ball) {
    const starts = this.schedule.starts
    const o = this.schedule.takeStart() * START_STRIDE
    const point = this._point
    point.x = starts[o] * SCALE; point.y = starts[o + 1] * SCALE
    ball.setTransform(point, starts[o + 4])
    point.x = starts[o + 2] * SCALE; point.y = starts[o + 3] * SCALE
    ball.setLinearVelocity(point)
    ball.setAngularVelocity(starts[o + 5])
    ball.setAwake(true)
  }
}
