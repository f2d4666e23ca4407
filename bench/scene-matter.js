/**
 * The benchmark scene in matter-js (px and ms, like its own examples).
 * - Pegs: static circles (matter-js builds a circle as a 10-sided polygon at
 *   these radii). Walls: matter-js has no segment shape, so each wall is a
 *   static rectangle 20 px thick whose inner face lies on the board's
 *   segment.
 * - Balls: dynamic circles with collisionFilter.group -1, so balls never
 *   collide with each other, only with pegs and walls. Air friction 0.
 * - Gravity 980 px/s²: gravity.y 1 with scale 0.00098 px/ms².
 * - Materials: matter-js mixes restitution by max and friction by min, our
 *   engine (and planck) by max and geometric mean; every body gets the mixed
 *   ball-on-plastic values so each contact sees the same restitution 0.6
 *   and friction sqrt(0.2·0.3). Solver iterations, slop and static friction
 *   are matter-js defaults.
 * - Step: Engine.update(engine, 1000 / 60). A landed ball is moved back to
 *   the top with Body.setPosition/setAngle/setVelocity/setAngularVelocity.
 */
import Matter from 'matter-js'
import { mixFriction, mixRestitution } from '../engine/materials.js'
import { SCENE, BALL_MATERIAL, PEG_MATERIAL, BallSchedule, START_STRIDE } from './plinko-scene.js'

const { Engine, Bodies, Body, Composite } = Matter

export const MATTER_WALL_THICKNESS = 20
const STEP_MS = SCENE.timestep * 1000

export class MatterScene {
  /**
   * @param {import('../engine/board.js').Board} board
   * @param {Float64Array} starts start table (plinko-scene.js)
   * @param {{ balls?: number, releaseEvery?: number }} [options]
   */
  constructor (board, starts, { balls = SCENE.balls, releaseEvery = SCENE.releaseEvery } = {}) {
    this.lineY = board.bucketLineY
    this.schedule = new BallSchedule(starts, balls, releaseEvery)
    const engine = Engine.create()
    engine.gravity.x = 0
    engine.gravity.y = 1
    engine.gravity.scale = SCENE.gravity / 1e6 // px/ms²
    this.engine = engine
    const surface = {
      restitution: mixRestitution(BALL_MATERIAL.restitution, PEG_MATERIAL.restitution),
      friction: mixFriction(BALL_MATERIAL.friction, PEG_MATERIAL.friction)
    }
    const statics = board.pegs.map((peg) => Bodies.circle(peg.x, peg.y, board.pegRadius, { isStatic: true, ...surface }))
    const centreX = board.width / 2
    for (const [x1, y1, x2, y2] of board.walls) {
      const dx = x2 - x1; const dy = y2 - y1
      const length = Math.sqrt(dx * dx + dy * dy)
      // Unit normal pointing away from the board's centre line.
      let nx = -dy / length; let ny = dx / length
      if (nx * ((x1 + x2) / 2 - centreX) < 0) { nx = -nx; ny = -ny }
      const half = MATTER_WALL_THICKNESS / 2
      statics.push(Bodies.rectangle((x1 + x2) / 2 + nx * half, (y1 + y2) / 2 + ny * half, length, MATTER_WALL_THICKNESS, {
        isStatic: true, angle: Math.atan2(dy, dx), ...surface
      }))
    }
    Composite.add(engine.world, statics)
    this.balls = []
    for (let k = 0; k < balls; k++) {
      this.balls.push(Bodies.circle(0, 0, board.ballRadius, {
        frictionAir: 0,
        collisionFilter: { group: -1 },
        ...surface
      }))
    }
    this._point = { x: 0, y: 0 }
  }

  step () {
    const schedule = this.schedule
    if (schedule.releaseDue()) {
      const ball = this.balls[schedule.released++]
      this._place(ball)
      Composite.add(this.engine.world, ball)
    }
    Engine.update(this.engine, STEP_MS)
    schedule.tick++
    const balls = this.balls
    for (let k = 0, n = schedule.released; k < n; k++) {
      if (schedule.ageAndCheck(k, balls[k].position.y, this.lineY)) this._place(balls[k])
    }
  }

  get landed () { return this.schedule.landed }
  get landedTicks () { return this.schedule.landedTicks }

  _place (ball) {
    const starts = this.schedule.starts
    const o = this.schedule.takeStart() * START_STRIDE
    const point = this._point
    point.x = starts[o]; point.y = starts[o + 1]
    Body.setPosition(ball, point)
    Body.setAngle(ball, starts[o + 4])
    // matter-js velocities are per 1000/60 ms.
    point.x = starts[o + 2] * SCENE.timestep; point.y = starts[o + 3] * SCENE.timestep
    Body.setVelocity(ball, point)
    Body.setAngularVelocity(ball, starts[o + 5] * SCENE.timestep)
  }
}
