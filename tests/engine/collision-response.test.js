import { describe, it, expect } from 'vitest'
import { World } from '../../engine/world.js'
import { METAL, HARD_PLASTIC } from '../../engine/materials.js'
import { RESTITUTION_THRESHOLD, LINEAR_SLOP } from '../../engine/contact-solver.js'

const bouncy = { density: 1, restitution: 1, friction: 0 }
const dead = { density: 1, restitution: 0, friction: 0 }

describe('collision response', () => {
  it('never increases total energy while a ball bounces and rolls on pegs and floor', () => {
    const world = new World()
    world.addStaticBox(0, 400, 600, 420, HARD_PLASTIC)
    for (let i = 0; i < 8; i++) world.addStaticCircle(80 + i * 60, 250 + (i % 2) * 30, 4, HARD_PLASTIC)
    world.addStaticSegment(0, 0, 0, 400, HARD_PLASTIC)
    world.addStaticSegment(600, 0, 600, 400, HARD_PLASTIC)
    for (let b = 0; b < 5; b++) {
      world.createCircle({ x: 90 + b * 97, y: 40, vx: 120 - b * 60, radius: 7, angularVelocity: b - 2, material: METAL, collidesWithBodies: false })
    }
    let previous = world.totalEnergy()
    const start = previous
    let worstRise = 0
    for (let i = 0; i < 1800; i++) {
      world.step()
      const energy = world.totalEnergy()
      worstRise = Math.max(worstRise, energy - previous)
      previous = energy
    }
    // Positional correction may lift a resting ball by a fraction of a pixel:
    // allow at most that much potential energy per step, and an overall loss.
    const ballWeight = 7.8 * Math.PI * 49 * 980
    expect(worstRise).toBeLessThan(ballWeight * 5 * LINEAR_SLOP)
    expect(previous).toBeLessThan(start)
  })

  it('keeps a ball at rest on a floor at rest, without sinking', () => {
    const world = new World()
    world.addStaticBox(0, 100, 200, 120, HARD_PLASTIC)
    const id = world.createCircle({ x: 100, y: 93, radius: 7, material: METAL })
    for (let i = 0; i < 120; i++) world.step()
    const settledY = world.yOf(id)
    for (let i = 0; i < 6000; i++) world.step()
    expect(world.yOf(id)).toBe(settledY)
    expect(world.vxOf(id)).toBe(0)
    expect(world.vyOf(id)).toBe(0)
    // Resting depth stays within the slop plus one step of gravity.
    const depth = world.yOf(id) + 7 - 100
    expect(depth).toBeGreaterThanOrEqual(0)
    expect(depth).toBeLessThan(LINEAR_SLOP + 980 / 3600)
  })

  it('applies j = -(1+e)·v_n/(1/m): a head-on hit on a static peg reverses the normal speed times e', () => {
    for (const e of [0, 0.5, 1]) {
      const world = new World({ gravityY: 0 })
      world.addStaticCircle(0, 0, 4, { restitution: e, friction: 0 })
      const id = world.createCircle({ x: -30, y: 0, vx: 600, radius: 7, material: { density: 1, restitution: 0, friction: 0 } })
      for (let i = 0; i < 30; i++) world.step()
      expect(world.vxOf(id)).toBeCloseTo(-600 * e, 9)
      expect(world.vyOf(id)).toBe(0)
    }
  })

  it('treats slow impacts as inelastic so resting contacts do not jitter', () => {
    const world = new World({ gravityY: 0 })
    world.addStaticBox(-10, 0, 10, 10, bouncy)
    const slow = RESTITUTION_THRESHOLD / 2
    const id = world.createCircle({ x: 0, y: -7 - slow / 60 / 2, vy: slow, radius: 7, material: bouncy })
    for (let i = 0; i < 3; i++) world.step()
    expect(world.vyOf(id)).toBeCloseTo(0, 12) // stopped, not bounced back at e·v
    expect(world.yOf(id)).toBeLessThan(-7 + LINEAR_SLOP + 1)
  })

  it('exchanges momentum between equal balls in a head-on elastic collision', () => {
    const world = new World({ gravityY: 0 })
    const a = world.createCircle({ x: 0, y: 0, vx: 300, radius: 7, material: bouncy })
    const b = world.createCircle({ x: 40, y: 0, vx: 0, radius: 7, material: bouncy })
    for (let i = 0; i < 30; i++) world.step()
    expect(world.vxOf(a)).toBeCloseTo(0, 9)
    expect(world.vxOf(b)).toBeCloseTo(300, 9)
  })

  it('conserves momentum in a glancing collision between free balls', () => {
    const world = new World({ gravityY: 0 })
    const a = world.createCircle({ x: 0, y: 0, vx: 300, vy: 10, radius: 7, material: METAL })
    const b = world.createCircle({ x: 40, y: 6, vx: -50, radius: 5, material: METAL })
    const mass = (id) => 1 / world.inverseMassOf(id)
    const px = () => mass(a) * world.vxOf(a) + mass(b) * world.vxOf(b)
    const py = () => mass(a) * world.vyOf(a) + mass(b) * world.vyOf(b)
    const before = [px(), py()]
    for (let i = 0; i < 30; i++) world.step()
    expect(px()).toBeCloseTo(before[0], 6)
    expect(py()).toBeCloseTo(before[1], 6)
    expect(world.vyOf(b)).not.toBe(0) // they did collide
  })

  it('applies Coulomb friction: a sliding ball picks up spin, bounded by μ·j', () => {
    const make = (friction) => {
      const world = new World({ gravityY: 0 })
      world.addStaticBox(-1000, 0, 1000, 20, { restitution: 0, friction })
      const id = world.createCircle({ x: 0, y: -8, vx: 200, vy: 200, radius: 7, material: { density: 1, restitution: 0, friction } })
      world.step()
      return { world, id }
    }
    const frictionless = make(0)
    expect(frictionless.world.angularVelocityOf(frictionless.id)).toBe(0)
    expect(frictionless.world.vxOf(frictionless.id)).toBe(200)
    const rough = make(0.2)
    // Normal impulse removes vy = 200 (per unit mass); friction may remove at most 0.2 * 200 of vx.
    expect(rough.world.vxOf(rough.id)).toBeCloseTo(200 - 0.2 * 200, 9)
    expect(rough.world.angularVelocityOf(rough.id)).not.toBe(0)
    const sticky = make(10)
    // With ample friction the contact point stops slipping: v = ω·r (rolling), reached in one impulse.
    const { world, id } = sticky
    expect(world.vxOf(id) - world.angularVelocityOf(id) * 7).toBeCloseTo(0, 6)
  })

  it('stops a fast ball on a wall segment and on a box face without passing through', () => {
    const world = new World({ gravityY: 0 })
    world.addStaticSegment(100, -100, 100, 100, dead)
    world.addStaticBox(-200, -10, -150, 10, dead)
    const right = world.createCircle({ x: 0, y: 0, vx: 1500, radius: 7, material: dead, collidesWithBodies: false })
    const left = world.createCircle({ x: 0, y: 0, vx: -1500, radius: 7, material: dead, collidesWithBodies: false })
    for (let i = 0; i < 60; i++) world.step()
    expect(world.xOf(right)).toBeLessThanOrEqual(100 - 7 + LINEAR_SLOP + 1e-9)
    expect(world.xOf(right)).toBeGreaterThan(100 - 7 - 1)
    expect(world.xOf(left)).toBeGreaterThanOrEqual(-150 + 7 - LINEAR_SLOP - 1e-9)
    expect(world.xOf(left)).toBeLessThan(-150 + 7 + 1)
  })

  it('slides a ball around a box corner it grazes instead of stopping it', () => {
    const world = new World({ gravityY: 0 })
    world.addStaticBox(-200, -10, -150, 10, dead)
    const id = world.createCircle({ x: 0, y: 12, vx: -1500, radius: 7, material: dead })
    for (let i = 0; i < 60; i++) world.step()
    expect(world.yOf(id)).toBeGreaterThanOrEqual(10 + 7 - 1) // pushed below the box, never inside it
    expect(world.vyOf(id)).toBeGreaterThan(0)
  })
})
