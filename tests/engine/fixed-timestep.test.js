import { describe, it, expect } from 'vitest'
import { FixedTimestep } from '../../engine/fixed-timestep.js'
import { World } from '../../engine/world.js'

describe('FixedTimestep', () => {
  it('turns elapsed time into whole steps and keeps the remainder as alpha', () => {
    const clock = new FixedTimestep({ timestep: 0.25, maxSteps: 10 })
    // Binary fractions, so the arithmetic is exact.
    expect(clock.advance(0.625)).toBe(2)
    expect(clock.alpha).toBe(0.5)
    expect(clock.advance(0.125)).toBe(1)
    expect(clock.alpha).toBe(0)
  })

  it('caps the steps of one call and drops the excess time (no spiral of death)', () => {
    const clock = new FixedTimestep({ timestep: 1 / 60, maxSteps: 5 })
    expect(clock.advance(10)).toBe(5)
    expect(clock.alpha).toBeGreaterThanOrEqual(0)
    expect(clock.alpha).toBeLessThan(1)
    expect(clock.droppedTime).toBeGreaterThan(9.8)
    expect(clock.advance(0)).toBe(0)
  })

  it('ignores negative and non-finite frame times', () => {
    const clock = new FixedTimestep({ timestep: 0.1, maxSteps: 3 })
    expect(clock.advance(-1)).toBe(0)
    expect(clock.advance(NaN)).toBe(0)
    expect(clock.advance(Infinity)).toBe(0)
    expect(clock.accumulator).toBe(0)
  })

  it('rejects bad settings', () => {
    expect(() => new FixedTimestep({ timestep: 0, maxSteps: 1 })).toThrow(RangeError)
    expect(() => new FixedTimestep({ timestep: 0.1, maxSteps: 0 })).toThrow(RangeError)
  })

  it('drives World.update: one step per timestep, alpha interpolates the pose', () => {
    const world = new World()
    const id = world.createCircle({ x: 0, y: 0, radius: 5 })
    const alpha = world.update(2.5 / 60)
    expect(world.tick).toBe(2)
    expect(alpha).toBeCloseTo(0.5, 9)
    const pose = world.interpolatedPose(id, alpha, [0, 0, 0])
    expect(pose[1]).toBeGreaterThan(world.previousYOf(id))
    expect(pose[1]).toBeLessThan(world.yOf(id))
  })
})
