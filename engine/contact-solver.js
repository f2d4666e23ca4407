import { mixRestitution, mixFriction } from './materials.js'
import { SWEEP_NX, SWEEP_NY, SWEEP_DEPTH } from './static-shapes.js'
import { BODY_X, BODY_Y, BODY_VX, BODY_VY, BODY_SPIN, BODY_RADIUS, BODY_INVERSE_MASS, BODY_INVERSE_INERTIA, BODY_RESTITUTION, BODY_FRICTION } from './body-layout.js'

// The body layout as module-private constants, which V8 folds into the code.
const X = BODY_X; const Y = BODY_Y; const VX = BODY_VX; const VY = BODY_VY; const SPIN = BODY_SPIN
const RADIUS = BODY_RADIUS; const INVERSE_MASS = BODY_INVERSE_MASS; const INVERSE_INERTIA = BODY_INVERSE_INERTIA
const RESTITUTION = BODY_RESTITUTION; const FRICTION = BODY_FRICTION

/**
 * Impulse-based contact response for circles, written against the world's
 * body state (World.state: one block of doubles per body, body-layout.js). Normal impulse j = -(1+e)·v_n / (1/m_A + 1/m_B) (the
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
 * The body at offset `i` of `b` against immovable shape `shape`, with the
 * normal (from the shape to the body) and depth in the sweep scratch
 * `contact` (SWEEP_* layout). All inputs come through arrays so the call
 * boxes no doubles.
 * @param {Float64Array} b the world's body state
 * @param {number} i the body's offset in it (id × BODY_STRIDE)
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
  const eBody = b[i + RESTITUTION]; const eShape = statics.restitution[shape]
  const restitution = eBody > eShape ? eBody : eShape
  const friction = Math.sqrt(b[i + FRICTION] * statics.friction[shape])
  const r = b[i + RADIUS]
  const invMass = b[i + INVERSE_MASS]
  const invInertia = b[i + INVERSE_INERTIA]
  let vx = b[i + VX]
  let vy = b[i + VY]
  let w = b[i + SPIN]
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
    b[i + VX] = vx
    b[i + VY] = vy
    b[i + SPIN] = w
  }
  const correction = depth - LINEAR_SLOP
  if (correction > 0) {
    b[i + X] += nx * correction * CORRECTION_FRACTION
    b[i + Y] += ny * correction * CORRECTION_FRACTION
  }
}

/**
 * Two moving circles at offsets i and j of `b` in contact; contact[0..2]
 * holds the normal (from j to i) and the depth.
 * @param {Float64Array} b the world's body state
 * @param {number} i @param {number} j offsets (id × BODY_STRIDE)
 * @param {Float64Array} contact
 */
export function solveBodyContact (b, i, j, contact) {
  const nx = contact[0]
  const ny = contact[1]
  const depth = contact[2]
  const restitution = mixRestitution(b[i + RESTITUTION], b[j + RESTITUTION])
  const friction = mixFriction(b[i + FRICTION], b[j + FRICTION])
  const ri = b[i + RADIUS]; const rj = b[j + RADIUS]
  const mi = b[i + INVERSE_MASS]; const mj = b[j + INVERSE_MASS]
  const Ii = b[i + INVERSE_INERTIA]; const Ij = b[j + INVERSE_INERTIA]
  const massSum = mi + mj
  if (massSum === 0) return
  const wi = b[i + SPIN]; const wj = b[j + SPIN]
  // Contact point velocities: i touches at -ri·n, j at +rj·n.
  const rvx = (b[i + VX] + wi * ri * ny) - (b[j + VX] - wj * rj * ny)
  const rvy = (b[i + VY] - wi * ri * nx) - (b[j + VY] + wj * rj * nx)
  const vn = rvx * nx + rvy * ny
  if (vn < 0) {
    const e = vn < -RESTITUTION_THRESHOLD ? restitution : 0
    const jn = -(1 + e) * vn / massSum
    b[i + VX] += jn * mi * nx; b[i + VY] += jn * mi * ny
    b[j + VX] -= jn * mj * nx; b[j + VY] -= jn * mj * ny
    const vt = -rvx * ny + rvy * nx
    const kt = massSum + ri * ri * Ii + rj * rj * Ij
    let jt = -vt / kt
    const maxFriction = friction * jn
    jt = jt > maxFriction ? maxFriction : (jt < -maxFriction ? -maxFriction : jt)
    b[i + VX] -= jt * mi * ny; b[i + VY] += jt * mi * nx
    b[j + VX] += jt * mj * ny; b[j + VY] -= jt * mj * nx
    b[i + SPIN] -= jt * ri * Ii
    b[j + SPIN] -= jt * rj * Ij
  }
  const correction = depth - LINEAR_SLOP
  if (correction > 0) {
    const share = correction * CORRECTION_FRACTION / massSum
    b[i + X] += nx * share * mi; b[i + Y] += ny * share * mi
    b[j + X] -= nx * share * mj; b[j + Y] -= ny * share * mj
  }
}
