import { createRandom } from './random.js'

/** Largest initial sideways speed (px/s) of a released ball. */
export const MAX_RELEASE_VX = 20
/** Largest initial downward speed (px/s). */
export const MAX_RELEASE_VY = 20
/** Largest initial spin (rad/s), either way. */
export const MAX_RELEASE_SPIN = 3
const TWO_PI = 6.283185307179586

/**
 * Where and how a ball is released, drawn from seedrandom(dropSeed) in a
 * fixed order: x, vx, vy, angle, spin. Physics decides everything after.
 * @param {import('./board.js').Board} board
 * @param {string} dropSeed
 */
export function dropInitialConditions (board, dropSeed) {
  if (typeof dropSeed !== 'string' || dropSeed.length === 0) throw new TypeError('dropSeed must be a non-empty string')
  const random = createRandom(dropSeed)
  const zone = board.dropZone
  return {
    x: zone.minX + (zone.maxX - zone.minX) * random(),
    y: zone.y,
    vx: (random() * 2 - 1) * MAX_RELEASE_VX,
    vy: random() * MAX_RELEASE_VY,
    angle: random() * TWO_PI,
    angularVelocity: (random() * 2 - 1) * MAX_RELEASE_SPIN
  }
}
