/**
 * Static (immovable, infinite-mass) shapes: circles (pegs) and segments
 * (walls; a box is stored as its four edges). Stored flat, by small integer
 * id. The narrow phase is continuous: it finds the first time of impact of
 * a moving circle along its straight path within a sub-step, so contacts are
 * resolved where the ball really touches, never after it has sunk in.
 * Inputs and outputs go through Float64Array scratch space so that no double
 * is boxed on the hot path.
 */

import { BODY_X, BODY_Y, BODY_RADIUS } from './body-layout.js'

export const SHAPE_CIRCLE = 0
export const SHAPE_SEGMENT = 1

/**
 * Float64 parameters stored per shape in `params`:
 * circle: cx, cy, radius; segment: x1, y1, x2, y2, unit normal nx, ny, 1/length².
 */
export const PARAMS_PER_SHAPE = 8

/** Layout of the sweep scratch array shared with the world. */
export const SWEEP_DX = 0
export const SWEEP_DY = 1
export const SWEEP_TIME = 2
export const SWEEP_NX = 3
export const SWEEP_NY = 4
export const SWEEP_DEPTH = 5
// Inputs of the point-against-disc sweep, also passed through the array.
const SWEEP_PX = 6
const SWEEP_PY = 7
const SWEEP_CX = 8
const SWEEP_CY = 9
const SWEEP_REACH = 10
export const SWEEP_SIZE = 11
/** px added to nearBox's reach, so rounding never leaves out a shape that is just in reach. */
const NEAR_TOLERANCE = 1e-6

export class StaticShapes {
  constructor () {
    this.count = 0
    this.kind = new Uint8Array(16)
    this.params = new Float64Array(16 * PARAMS_PER_SHAPE)
    this.restitution = new Float64Array(16)
    this.friction = new Float64Array(16)
  }

  _add (kind, material) {
    if (this.count === this.kind.length) this._grow()
    const id = this.count++
    this.kind[id] = kind
    this.restitution[id] = material.restitution
    this.friction[id] = material.friction
    return id
  }

  _grow () {
    const size = this.kind.length * 2
    const grow = (Type, old, n) => { const a = new Type(n); a.set(old); return a }
    this.kind = grow(Uint8Array, this.kind, size)
    this.params = grow(Float64Array, this.params, size * PARAMS_PER_SHAPE)
    this.restitution = grow(Float64Array, this.restitution, size)
    this.friction = grow(Float64Array, this.friction, size)
  }

  addCircle (x, y, radius, material) {
    if (!Number.isFinite(x + y) || !(radius > 0 && radius < Infinity)) throw new RangeError('circle needs a finite centre and radius > 0')
    const id = this._add(SHAPE_CIRCLE, material)
    const p = id * PARAMS_PER_SHAPE
    this.params[p] = x
    this.params[p + 1] = y
    this.params[p + 2] = radius
    return id
  }

  addSegment (x1, y1, x2, y2, material) {
    if (!Number.isFinite(x1 + y1 + x2 + y2)) throw new RangeError('segment ends must be finite')
    if (x1 === x2 && y1 === y2) throw new RangeError('segment must have two distinct ends')
    const id = this._add(SHAPE_SEGMENT, material)
    const p = id * PARAMS_PER_SHAPE
    const ex = x2 - x1
    const ey = y2 - y1
    const length2 = ex * ex + ey * ey
    const length = Math.sqrt(length2)
    this.params[p] = x1
    this.params[p + 1] = y1
    this.params[p + 2] = x2
    this.params[p + 3] = y2
    this.params[p + 4] = -ey / length
    this.params[p + 5] = ex / length
    this.params[p + 6] = 1 / length2
    return id
  }

  /** Adds an axis-aligned box as its four edges; returns the first edge's id. */
  addBox (minX, minY, maxX, maxY, material) {
    if (!(maxX > minX && maxY > minY)) throw new RangeError('box needs min < max on both axes')
    const first = this.addSegment(minX, minY, maxX, minY, material)
    this.addSegment(maxX, minY, maxX, maxY, material)
    this.addSegment(maxX, maxY, minX, maxY, material)
    this.addSegment(minX, maxY, minX, minY, material)
    return first
  }

  /** Axis-aligned bounds of shape `id` grown by `margin`, into out[0..3]. */
  boundsOf (id, margin, out) {
    const p = id * PARAMS_PER_SHAPE
    const a = this.params[p]; const b = this.params[p + 1]
    const c = this.params[p + 2]; const d = this.params[p + 3]
    if (this.kind[id] === SHAPE_CIRCLE) {
      out[0] = a - c - margin; out[1] = b - c - margin
      out[2] = a + c + margin; out[3] = b + c + margin
    } else {
      out[0] = (a < c ? a : c) - margin; out[1] = (b < d ? b : d) - margin
      out[2] = (a > c ? a : c) + margin; out[3] = (b > d ? b : d) + margin
    }
  }

  /**
   * Whether some point of the box [minX,maxX]x[minY,maxY] lies within
   * `margin` of shape `id`: exact for a circle (give or take NEAR_TOLERANCE),
   * conservative for a segment (may answer true when close).
   */
  nearBox (id, margin, minX, minY, maxX, maxY) {
    if (this.kind[id] === SHAPE_CIRCLE) {
      // Exact for a disc: its centre's distance to the box, against its radius plus the margin.
      const p = id * PARAMS_PER_SHAPE
      const cx = this.params[p]; const cy = this.params[p + 1]
      const dx = cx < minX ? minX - cx : (cx > maxX ? cx - maxX : 0)
      const dy = cy < minY ? minY - cy : (cy > maxY ? cy - maxY : 0)
      const reach = margin + this.params[p + 2] + NEAR_TOLERANCE
      return dx * dx + dy * dy <= reach * reach
    }
    const halfW = (maxX - minX) / 2
    const halfH = (maxY - minY) / 2
    // Distance from the box centre against its half diagonal plus the margin.
    const reach = margin + Math.sqrt(halfW * halfW + halfH * halfH)
    return this.distanceSquaredTo(id, minX + halfW, minY + halfH) <= reach * reach
  }

  /** Squared distance from a point to the surface of shape `id` (0 inside a circle). */
  distanceSquaredTo (id, x, y) {
    const p = id * PARAMS_PER_SHAPE
    const params = this.params
    if (this.kind[id] === SHAPE_CIRCLE) {
      const dx = x - params[p]; const dy = y - params[p + 1]
      const outside = Math.sqrt(dx * dx + dy * dy) - params[p + 2]
      return outside > 0 ? outside * outside : 0
    }
    const ax = params[p]; const ay = params[p + 1]
    const ex = params[p + 2] - ax; const ey = params[p + 3] - ay
    let u = ((x - ax) * ex + (y - ay) * ey) * params[p + 6]
    u = u < 0 ? 0 : (u > 1 ? 1 : u)
    const dx = x - (ax + ex * u); const dy = y - (ay + ey * u)
    return dx * dx + dy * dy
  }

  /**
   * Continuous narrow phase: the dynamic circle at offset `i` of the body
   * state `bodies` (World.state, body-layout.js), moving by
   * (io[SWEEP_DX], io[SWEEP_DY]) in a straight line, against shape `id`.
   * Returns true when it touches the shape while approaching it, writing
   * the time of impact in [0, 1], the unit normal (from shape to circle)
   * and the overlap at that time (0 unless already overlapping) into io.
   * @param {number} id
   * @param {Float64Array} bodies the world's body state
   * @param {number} i the body's offset in it (id × BODY_STRIDE)
   * @param {Float64Array} io
   */
  sweep (id, bodies, i, io) {
    return this.kind[id] === SHAPE_CIRCLE ? this.sweepCircle(id, bodies, i, io) : this.sweepSegment(id, bodies, i, io)
  }

  sweepCircle (id, bodies, i, io) {
    const p = id * PARAMS_PER_SHAPE
    io[SWEEP_PX] = bodies[i + BODY_X]; io[SWEEP_PY] = bodies[i + BODY_Y]
    io[SWEEP_CX] = this.params[p]; io[SWEEP_CY] = this.params[p + 1]
    io[SWEEP_REACH] = bodies[i + BODY_RADIUS] + this.params[p + 2]
    return sweepPoint(io)
  }

  sweepSegment (id, bodies, i, io) {
    const params = this.params
    const p = id * PARAMS_PER_SHAPE
    const x = bodies[i + BODY_X]; const y = bodies[i + BODY_Y]
    const reach = bodies[i + BODY_RADIUS]
    const ax = params[p]; const ay = params[p + 1]
    const bx = params[p + 2]; const by = params[p + 3]
    const ex = bx - ax; const ey = by - ay
    const dx = io[SWEEP_DX]; const dy = io[SWEEP_DY]
    // Already touching (closest point within reach): contact now if approaching.
    let u = ((x - ax) * ex + (y - ay) * ey) * params[p + 6]
    u = u < 0 ? 0 : (u > 1 ? 1 : u)
    const qx = x - (ax + ex * u); const qy = y - (ay + ey * u)
    const dist2 = qx * qx + qy * qy
    if (dist2 <= reach * reach) {
      if (qx * dx + qy * dy >= 0) return false
      io[SWEEP_PX] = qx; io[SWEEP_PY] = qy; io[SWEEP_REACH] = reach
      return touchingNow(io, dist2)
    }
    // The face: signed distance to the line falls linearly along the path.
    let nx = params[p + 4]; let ny = params[p + 5]
    let side = (x - ax) * nx + (y - ay) * ny
    if (side < 0) { nx = -nx; ny = -ny; side = -side }
    const approach = dx * nx + dy * ny
    if (approach < 0 && side >= reach) {
      const t = (side - reach) / -approach
      if (t > 1) return false // the line is not reached in this sub-step
      const cx = x + dx * t; const cy = y + dy * t
      const v = ((cx - ax) * ex + (cy - ay) * ey) * params[p + 6]
      if (v >= 0 && v <= 1) {
        io[SWEEP_TIME] = t; io[SWEEP_NX] = nx; io[SWEEP_NY] = ny; io[SWEEP_DEPTH] = 0
        return true
      }
    }
    // Otherwise only an end can be hit first: take the earlier.
    io[SWEEP_PX] = x; io[SWEEP_PY] = y; io[SWEEP_REACH] = reach
    io[SWEEP_CX] = ax; io[SWEEP_CY] = ay
    const hitA = sweepPoint(io)
    const tA = io[SWEEP_TIME]; const nxA = io[SWEEP_NX]; const nyA = io[SWEEP_NY]; const depthA = io[SWEEP_DEPTH]
    io[SWEEP_PX] = x; io[SWEEP_PY] = y; io[SWEEP_REACH] = reach
    io[SWEEP_CX] = bx; io[SWEEP_CY] = by
    const hitB = sweepPoint(io)
    if (hitA && (!hitB || tA <= io[SWEEP_TIME])) {
      io[SWEEP_TIME] = tA; io[SWEEP_NX] = nxA; io[SWEEP_NY] = nyA; io[SWEEP_DEPTH] = depthA
      return true
    }
    return hitB
  }
}

/**
 * A point moving from io[SWEEP_PX, SWEEP_PY] by io[SWEEP_DX, SWEEP_DY]
 * against a disc of radius io[SWEEP_REACH] at io[SWEEP_CX, SWEEP_CY]:
 * solves |m + t·d| = reach for the first t in [0, 1].
 */
function sweepPoint (io) {
  const dx = io[SWEEP_DX]; const dy = io[SWEEP_DY]
  const mx = io[SWEEP_PX] - io[SWEEP_CX]; const my = io[SWEEP_PY] - io[SWEEP_CY]
  const reach = io[SWEEP_REACH]
  const b = mx * dx + my * dy
  if (b >= 0) return false // moving away or along
  const c = mx * mx + my * my - reach * reach
  if (c <= 0) {
    io[SWEEP_PX] = mx; io[SWEEP_PY] = my
    return touchingNow(io, c + reach * reach)
  }
  const a = dx * dx + dy * dy
  const discriminant = b * b - a * c
  if (discriminant < 0) return false
  // The smaller root (-b - √D)/a, written as c/(-b + √D): no cancellation,
  // and no division by a vanishing a when the body barely moves.
  const t = c / (-b + Math.sqrt(discriminant))
  if (t > 1) return false
  io[SWEEP_TIME] = t
  io[SWEEP_NX] = (mx + dx * t) / reach
  io[SWEEP_NY] = (my + dy * t) / reach
  io[SWEEP_DEPTH] = 0
  return true
}

// Contact at t = 0 for a circle already within reach: io[SWEEP_PX, SWEEP_PY]
// holds the offset from the shape to the centre, `dist2` its squared length.
function touchingNow (io, dist2) {
  io[SWEEP_TIME] = 0
  if (dist2 > 0) {
    const dist = Math.sqrt(dist2)
    io[SWEEP_NX] = io[SWEEP_PX] / dist; io[SWEEP_NY] = io[SWEEP_PY] / dist
    io[SWEEP_DEPTH] = io[SWEEP_REACH] - dist
  } else {
    // Centre exactly on the shape: push straight up, as gravity would want.
    io[SWEEP_NX] = 0; io[SWEEP_NY] = -1; io[SWEEP_DEPTH] = io[SWEEP_REACH]
  }
  return true
}
