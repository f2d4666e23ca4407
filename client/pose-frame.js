/**
 * A frame's balls as the painter reads them (board-painter.js): one
 * Float64Array, STRIDE numbers a ball, small enough to hand to a worker
 * every frame (transferred, then handed back for reuse) instead of the
 * pose objects and their whole trajectories. Per ball: x, y, angle, alpha,
 * mine (1 or 0), the trail's point count, then up to TRAIL_POINTS (x, y)
 * points of its trail, newest first (board px, as doubles: the drawn place
 * is the engine's to the bit, as it was before the worker).
 */
export const TRAIL_TICKS = 7
export const TRAIL_POINTS = TRAIL_TICKS + 1
export const STRIDE = 6 + 2 * TRAIL_POINTS

/** A buffer for `count` balls (room for more, so a growing room reallocates rarely). */
export function poseBuffer (count) {
  return new Float64Array(STRIDE * Math.max(32, Math.ceil(count * 1.5)))
}

/**
 * Writes `poses` into `out` (its length at least STRIDE * poses.length).
 * A trail is the ball's last TRAIL_TICKS ticks of its simulated path,
 * shifted as the ball is drawn (ox, oy), for balls in flight only.
 * @param {import('./room-view.js').BallPose[]} poses @param {Float64Array} out
 */
export function packPoses (poses, out) {
  for (let b = 0; b < poses.length; b++) {
    const pose = poses[b]
    const o = b * STRIDE
    out[o] = pose.x
    out[o + 1] = pose.y
    out[o + 2] = pose.angle
    out[o + 3] = pose.alpha
    out[o + 4] = pose.mine ? 1 : 0
    let points = 0
    const t = pose.trajectory
    const newest = Math.floor(pose.age ?? 0)
    if (t && pose.alpha >= 1 && newest >= 1) {
      const ox = pose.ox ?? 0
      const oy = pose.oy ?? 0
      for (let i = newest; i >= Math.max(0, newest - TRAIL_TICKS); i--) {
        out[o + 6 + 2 * points] = t[3 * i] + ox
        out[o + 7 + 2 * points] = t[3 * i + 1] + oy
        points++
      }
    }
    out[o + 5] = points
  }
  return poses.length
}
