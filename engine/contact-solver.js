import { mixRestitution, mixFriction } from './materials.js'
import { SWEEP_NX, SWEEP_NY, SWEEP_DEPTH } from './static-shapes.js'

/**
 * Impulse-based contact response for circles, written against the world's
 * flat body arrays. Normal impulse j = -(1+e)·v_n / (1/m_A + 1/m_B) (the
 * normal passes through a circle's centre, so it has no angular term);
 * Coulomb friction along the tangent, clamped to μ·j, spins the ball; then a
 * positional correction pushes the bodies apart by most of the depth beyond
 * a small slop, so resting contact neither sinks nor jitters.
 */

/** Below this approach speed (px/s) a contact is treated as inelastic, so resting bodies stop bouncing. */
export const RESTITUTION_THRESHOLD = 30
/** Penetration (px) allowed without correction; keeps resting contacts stable. */
export const LINEAR_SLOP = 0.05
/** Fraction of the remaining penetration removed per solve. */
export const CORRECTION_FRACTION = 0.8

/**
 * @typedef {object} BodyArrays
 * @property {Float64Array} x @property {Float64Array} y
 * @property {Float64Array} vx @property {Float64Array} vy
 * @property {Float64Array} angularVelocity @property {Float64Array} radius
 * @property {Float64Array} inverseMass @property {Float64Array} inverseInertia
 */

/**
 * Body `i` against immovable shape `shape`, with the normal (from the shape
 * to the body) and depth in the sweep scratch `contact` (SWEEP_* layout).
 * All inputs come through arrays so the call boxes no doubles.
 * @param {BodyArrays & { restitution: Float64Array, friction: Float64Array }} b
 * @param {number} i
 * @param {{ restitution: Float64Array, friction: Float64Array }} statics
 * @param {number} shape
 * @param {Float64Array} contact
 */
export function solveStaticContact (b, i, statics, shape, contact) {
  const nx = contact[SWEEP_NX]
  const ny = contact[SWEEP_NY]
  const depth = contact[SWEEP_DEPTH]
  // The mixing rules of materials.js, written out: a call returning a double
  // that V8 does not inline would allocate on every contact.
  const eBody = b.restitution[i]; const eShape = statics.restitution[shape]
  const restitution = eBody > eShape ? eBody : eShape
  const friction = Math.sqrt(b.friction[i] * statics.friction[shape])
  const r = b.radius[i]
  const invMass = b.inverseMass[i]
  const invInertia = b.inverseInertia[i]
  let vx = b.vx[i]
  let vy = b.vy[i]
  let w = b.angularVelocity[i]
  // Velocity of the contact point (at -r·n from the centre): v + ω × (-r n).
  const cvx = vx + w * r * ny
  const cvy = vy - w * r * nx
  const vn = cvx * nx + cvy * ny
  if (vn < 0) {
    const e = vn < -RESTITUTION_THRESHOLD ? restitution : 0
    const jn = -(1 + e) * vn / invMass
    vx += jn * invMass * nx
    vy += jn * invMass * ny
    // Tangent t = (-ny, nx); the normal impulse left the tangential speed as it was.
    const vt = -cvx * ny + cvy * nx
    const kt = invMass + r * r * invInertia
    let jt = -vt / kt
    const maxFriction = friction * jn
    jt = jt > maxFriction ? maxFriction : (jt < -maxFriction ? -maxFriction : jt)
    vx -= jt * invMass * ny
    vy += jt * invMass * nx
    // Torque arm (-r n) × t = -r.
    w -= jt * r * invInertia
    b.vx[i] = vx
    b.vy[i] = vy
    b.angularVelocity[i] = w
  }
  const correction = depth - LINEAR_SLOP
  if (correction > 0) {
    b.x[i] += nx * correction * CORRECTION_FRACTION
    b.y[i] += ny * correction * CORRECTION_FRACTION
  }
}

/**
 * Two moving circles i and j in contact; contact[0..2] holds the normal
 * (from j to i) and the depth.
 * @param {BodyArrays & { restitution: Float64Array, friction: Float64Array }} b
 * @param {number} i @param {number} j
 * @param {Float64Array} contact
 */
export function solveBodyContact (b, i, j, contact) {
  const nx = contact[0]
  const ny = contact[1]
  const depth = contact[2]
  const restitution = mixRestitution(b.restitution[i], b.restitution[j])
  const friction = mixFriction(b.friction[i], b.friction[j])
  const ri = b.radius[i]; const rj = b.radius[j]
  const mi = b.inverseMass[i]; const mj = b.inverseMass[j]
  const Ii = b.inverseInertia[i]; const Ij = b.inverseInertia[j]
  const massSum = mi + mj
  if (massSum === 0) return
  const wi = b.angularVelocity[i]; const wj = b.angularVelocity[j]
  // Contact point velocities: i touches at -ri·n, j at +rj·n.
  const rvx = (b.vx[i] + wi * ri * ny) - (b.vx[j] - wj * rj * ny)
  const rvy = (b.vy[i] - wi * ri * nx) - (b.vy[j] + wj * rj * nx)
  const vn = rvx * nx + rvy * ny
  if (vn < 0) {
    const e = vn < -RESTITUTION_THRESHOLD ? restitution : 0
    const jn = -(1 + e) * vn / massSum
    b.vx[i] += jn * mi * nx; b.vy[i] += jn * mi * ny
    b.vx[j] -= jn * mj * nx; b.vy[j] -= jn * mj * ny
    const vt = -rvx * ny + rvy * nx
    const kt = massSum + ri * ri * Ii + rj * rj * Ij
    let jt = -vt / kt
    const maxFriction = friction * jn
    jt = jt > maxFriction ? maxFriction : (jt < -maxFriction ? -maxFriction : jt)
    b.vx[i] -= jt * mi * ny; b.vy[i] += jt * mi * nx
    b.vx[j] += jt * mj * ny; b.vy[j] -= jt * mj * nx
    b.angularVelocity[i] -= jt * ri * Ii
    b.angularVelocity[j] -= jt * rj * Ij
  }
  const correction = depth - LINEAR_SLOP
  if (correction > 0) {
    const share = correction * CORRECTION_FRACTION / massSum
    b.x[i] += nx * share * mi; b.y[i] += ny * share * mi
    b.x[j] -= nx * share * mj; b.y[j] -= ny * share * mj
  }
}
