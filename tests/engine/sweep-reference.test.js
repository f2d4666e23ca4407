import { describe, it, expect } from 'vitest'
import seedrandom from 'seedrandom'
import { World, MAX_TRAVEL_PER_SUBSTEP, MAX_SUBSTEPS, MAX_IMPACTS_PER_SUBSTEP } from '../../engine/world.js'
import { SWEEP_DX, SWEEP_DY, SWEEP_TIME } from '../../engine/static-shapes.js'
import { solveStaticContact } from '../../engine/contact-solver.js'
import { BODY_STRIDE, BODY_X, BODY_Y, BODY_VX, BODY_VY, BODY_ANGLE, BODY_SPIN, BODY_RADIUS, BODY_ALIVE, BODY_PREVIOUS_X, BODY_PREVIOUS_Y, BODY_PREVIOUS_ANGLE } from '../../engine/body-layout.js'
import { createBoard, ENGINE_VERSIONS } from '../../engine/index.js'

/**
 * The world sweeps pegs inline, with a call-free fast loop for bodies that
 * hit nothing; StaticShapes.sweep() is the one reference time of impact
 * (circle and segment). This world moves every body the plain way: each
 * sub-step's path against every candidate through StaticShapes.sweep(),
 * earliest impact first. Both must give the same bits, contact after
 * contact, on boards of every engine version and on random scenes.
 */
const TWO_PI = 6.283185307179586

class ReferenceWorld extends World {
  _advanceBodies (count) {
    const st = this.state
    const dt = this.timestep
    const absGx = Math.abs(this.gravityX); const absGy = Math.abs(this.gravityY)
    const grid = this.staticGrid
    for (let i = 0; i < count; i++) {
      const b = i * BODY_STRIDE
      if (st[b + BODY_ALIVE] !== 1) continue
      st[b + BODY_PREVIOUS_X] = st[b + BODY_X]; st[b + BODY_PREVIOUS_Y] = st[b + BODY_Y]; st[b + BODY_PREVIOUS_ANGLE] = st[b + BODY_ANGLE]
      let vx = st[b + BODY_VX]; let vy = st[b + BODY_VY]; let angle = st[b + BODY_ANGLE]
      const speedX = Math.abs(vx) + absGx * dt
      const speedY = Math.abs(vy) + absGy * dt
      const travel2 = (speedX * speedX + speedY * speedY) * dt * dt
      const maxTravel = st[b + BODY_RADIUS] * MAX_TRAVEL_PER_SUBSTEP
      let substeps = 1
      while (substeps < MAX_SUBSTEPS && travel2 > substeps * substeps * maxTravel * maxTravel) substeps++
      const h = dt / substeps
      for (let s = 0; s < substeps; s++) {
        vx += this.gravityX * h
        vy += this.gravityY * h
        angle += st[b + BODY_SPIN] * h
        if (angle >= TWO_PI || angle < 0) angle -= Math.floor(angle / TWO_PI) * TWO_PI
        let remaining = 1
        for (let impact = 0; impact < MAX_IMPACTS_PER_SUBSTEP && remaining > 0; impact++) {
          const x = st[b + BODY_X]; const y = st[b + BODY_Y]
          const dx = vx * h * remaining; const dy = vy * h * remaining
          let first = -1
          let firstTime = 2
          const contact = new Float64Array(this._sweep.length)
          const cell = grid.cellAt(x, y)
          if (cell >= 0) {
            for (let k = grid.cellStart[cell]; k < grid.cellStart[cell + 1]; k++) {
              const io = new Float64Array(this._sweep.length)
              io[SWEEP_DX] = dx; io[SWEEP_DY] = dy
              if (this.statics.sweep(grid.items[k], st, b, io) && io[SWEEP_TIME] < firstTime) {
                first = grid.items[k]
                firstTime = io[SWEEP_TIME]
                contact.set(io)
              }
            }
          }
          if (first < 0) { st[b + BODY_X] = x + dx; st[b + BODY_Y] = y + dy; break }
          st[b + BODY_X] = x + dx * firstTime; st[b + BODY_Y] = y + dy * firstTime
          remaining -= remaining * firstTime
          st[b + BODY_VX] = vx; st[b + BODY_VY] = vy
          solveStaticContact(st, b, this.statics, first, contact)
          vx = st[b + BODY_VX]; vy = st[b + BODY_VY]
        }
      }
      st[b + BODY_VX] = vx; st[b + BODY_VY] = vy; st[b + BODY_ANGLE] = angle
    }
  }
}

/** The same static shapes in a world of each kind. */
function pair (build) {
  const worlds = [new World(build.options), new ReferenceWorld(build.options)]
  for (const world of worlds) build.shapes(world)
  return worlds
}

function expectSameBits (fast, reference, label) {
  expect(fast.stateHash(), label).toBe(reference.stateHash())
}

describe('inline sweeps against the reference time of impact', () => {
  it.each(ENGINE_VERSIONS)('give the same bits for 600 balls on the 16-row board of engine %s', (engineVersion) => {
    const board = createBoard({ rows: 16, risk: 'high', engineVersion })
    const [fast, reference] = pair({
      options: { maxBodyRadius: board.ballRadius, staticCellSize: board.ballRadius },
      shapes: (world) => {
        for (const peg of board.pegs) world.addStaticCircle(peg.x, peg.y, board.pegRadius, board.pegMaterial)
        for (const [x1, y1, x2, y2] of board.walls) world.addStaticSegment(x1, y1, x2, y2, board.pegMaterial)
      }
    })
    const random = seedrandom(`sweep-reference-${engineVersion}`)
    for (let n = 0; n < 600; n++) {
      // Anywhere over the board, any direction, up to fast enough to need several sub-steps.
      const def = {
        x: board.bucketLeftX + random() * (board.width - 2 * board.bucketLeftX),
        y: board.dropZone.y + random() * (board.bucketLineY - board.dropZone.y),
        vx: (random() * 2 - 1) * 400,
        vy: (random() * 2 - 1) * 400,
        angularVelocity: (random() * 2 - 1) * 20,
        radius: board.ballRadius,
        material: board.ballMaterial,
        collidesWithBodies: false
      }
      fast.createCircle(def)
      reference.createCircle(def)
    }
    for (let tick = 1; tick <= 240; tick++) {
      fast.step()
      reference.step()
      if (tick % 10 === 0) expectSameBits(fast, reference, `engine ${engineVersion}, tick ${tick}`)
    }
  })

  it('give the same bits on random scenes of pegs, walls and boxes, grazing and head-on', () => {
    const random = seedrandom('sweep-reference-scenes')
    for (let scene = 0; scene < 30; scene++) {
      const radius = 1 + random() * 9
      const material = { density: 1, restitution: random(), friction: random() }
      const circles = Array.from({ length: 40 }, () => [random() * 400, random() * 400, 0.5 + random() * 8])
      const segments = Array.from({ length: 8 }, () => [random() * 400, random() * 400, random() * 400, random() * 400])
      const [fast, reference] = pair({
        options: { maxBodyRadius: radius, staticCellSize: radius * (0.5 + random() * 3) },
        shapes: (world) => {
          for (const [x, y, r] of circles) world.addStaticCircle(x, y, r, material)
          for (const [x1, y1, x2, y2] of segments) world.addStaticSegment(x1, y1, x2, y2, material)
          world.addStaticBox(0, 0, 400, 400, material)
        }
      })
      for (let n = 0; n < 60; n++) {
        const def = { x: 20 + random() * 360, y: 20 + random() * 360, vx: (random() * 2 - 1) * 900, vy: (random() * 2 - 1) * 900, radius: radius * (0.3 + 0.7 * random()), angularVelocity: (random() * 2 - 1) * 30, collidesWithBodies: false, material: { density: 7, restitution: random(), friction: random() } }
        fast.createCircle(def)
        reference.createCircle(def)
      }
      for (let tick = 1; tick <= 200; tick++) {
        fast.step()
        reference.step()
      }
      expectSameBits(fast, reference, `scene ${scene}`)
    }
  })
})
