/**
 * The frame format the board painter reads (client/pose-frame.js), in
 * Node: what the page hands the worker each frame must draw what the pose
 * objects describe — each ball's place, spin, fade and owner, and its trail
 * (the last ticks of its simulated path, shifted as the ball is drawn) for
 * balls in flight only.
 */
import { describe, it, expect } from 'vitest'
import { packPoses, poseBuffer, STRIDE, TRAIL_TICKS } from '../../client/pose-frame.js'

/** A straight path: tick i at (10 i, 20 i), angle i / 10. */
function path (ticks) {
  const t = new Float64Array(3 * (ticks + 1))
  for (let i = 0; i <= ticks; i++) t.set([10 * i, 20 * i, i / 10], 3 * i)
  return t
}

describe('pose frame', () => {
  it('packs each ball and the last ticks of its path, shifted as drawn, newest first', () => {
    const trajectory = path(40)
    const poses = [
      { x: 301.5, y: 602.25, angle: 3.05, alpha: 1, mine: true, trajectory, age: 30.5, ox: 1.5, oy: 2.25 },
      { x: 15, y: 30, angle: 0.1, alpha: 1, mine: false, trajectory, age: 1.2, ox: 0, oy: 0 },
      // Landed (fading): no trail. A replay's pose: no trajectory, no trail.
      { x: 400, y: 800, angle: 4, alpha: 0.5, mine: false, trajectory, age: 3, ox: 0, oy: 0 },
      { x: 5, y: 6, angle: 7, alpha: 1, mine: true }
    ]
    const out = poseBuffer(poses.length)
    expect(out.length).toBeGreaterThanOrEqual(STRIDE * poses.length)
    expect(packPoses(poses, out)).toBe(4)
    const ball = (b) => Array.from(out.subarray(b * STRIDE, b * STRIDE + 6))
    const trail = (b) => {
      const points = []
      for (let p = 0; p < out[b * STRIDE + 5]; p++) points.push([out[b * STRIDE + 6 + 2 * p], out[b * STRIDE + 7 + 2 * p]])
      return points
    }
    expect(ball(0)).toEqual([301.5, 602.25, 3.05, 1, 1, TRAIL_TICKS + 1])
    expect(trail(0)).toEqual(Array.from({ length: TRAIL_TICKS + 1 }, (_, k) => [10 * (30 - k) + 1.5, 20 * (30 - k) + 2.25]))
    // Released a tick ago: the trail reaches back to the drop, no further.
    expect(trail(1)).toEqual([[10, 20], [0, 0]])
    expect(ball(1)[4]).toBe(0)
    expect(ball(2)).toEqual([400, 800, 4, 0.5, 0, 0])
    expect(ball(3)).toEqual([5, 6, 7, 1, 1, 0])
  })
})
