import { describe, it, expect } from 'vitest'
import { World } from '../../engine/world.js'

describe('semi-implicit Euler integration', () => {
  it('updates velocity first, then position with the new velocity', () => {
    // A large body moves less than its radius per step, so no sub-steps split dt.
    const world = new World({ gravityY: 600, timestep: 0.1 })
    const id = world.createCircle({ x: 0, y: 0, vx: 10, radius: 25 })
    world.step()
    // v1 = v0 + g·dt = 60; y1 = y0 + v1·dt = 6 (explicit Euler would give 0)
    expect(world.vyOf(id)).toBeCloseTo(60, 12)
    expect(world.yOf(id)).toBeCloseTo(6, 12)
    expect(world.xOf(id)).toBeCloseTo(1, 12)
    world.step()
    expect(world.vyOf(id)).toBeCloseTo(120, 12)
    expect(world.yOf(id)).toBeCloseTo(18, 12)
  })

  it('matches the closed form of semi-implicit Euler over many steps in free fall', () => {
    const world = new World() // 980 px/s², 1/60 s
    const id = world.createCircle({ x: 0, y: 0, radius: 5 })
    const n = 120
    for (let i = 0; i < n; i++) world.step()
    const dt = 1 / 60
    // Sub-steps split dt, so velocity still gains exactly g·dt per step and the
    // position stays within 1% of the continuous solution.
    expect(world.vyOf(id)).toBeCloseTo(980 * dt * n, 6)
    const exact = 0.5 * 980 * (dt * n) ** 2
    expect(Math.abs(world.yOf(id) - exact) / exact).toBeLessThan(0.01)
  })

  it('integrates the angle from the angular velocity and keeps it in [0, 2π)', () => {
    const world = new World({ gravityY: 0 })
    const id = world.createCircle({ x: 0, y: 0, radius: 5, angularVelocity: 30 })
    for (let i = 0; i < 60; i++) world.step()
    expect(world.angleOf(id)).toBeGreaterThanOrEqual(0)
    expect(world.angleOf(id)).toBeLessThan(2 * Math.PI)
    expect(world.angleOf(id)).toBeCloseTo(30 % (2 * Math.PI), 6)
  })

  it('rejects invalid bodies', () => {
    const world = new World()
    expect(() => world.createCircle({ x: 0, y: 0, radius: 0 })).toThrow(RangeError)
    expect(() => world.createCircle({ x: NaN, y: 0, radius: 5 })).toThrow(RangeError)
    expect(() => world.createCircle({ x: 0, y: 0, radius: 1000 })).toThrow(RangeError)
    expect(() => world.destroyBody(42)).toThrow(RangeError)
  })

  it('reuses freed body ids lowest first', () => {
    const world = new World()
    const ids = [0, 1, 2, 3].map((x) => world.createCircle({ x: x * 40, y: 0, radius: 5 }))
    world.destroyBody(ids[2])
    world.destroyBody(ids[0])
    expect(world.createCircle({ x: 0, y: 0, radius: 5 })).toBe(0)
    expect(world.createCircle({ x: 0, y: 0, radius: 5 })).toBe(2)
    expect(world.liveBodyCount()).toBe(4)
  })
})
