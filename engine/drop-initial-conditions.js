import { createRandom } from './random.js'

const TWO_PI = 6.283185307179586

/**
 * Where and how a ball is released, drawn from seedrandom(dropSeed) in a
 * fixed order: x, vx, vy, angle, spin, within the board's drop zone and its
 * version's release bounds (board.release). Physics decides everything after.
 * @param {import('./board.js').Board} board
 * @param {string} dropSeed
 */
export function dropInitialConditions (board, dropSeed) {
  if (typeof dropSeed !== 'string' || dropSeed.length === 0) throw new TypeError('dropSeed must be a non-empty string')
  const random = createRandom(dropSeed)
  const zone = board.dropZone
  const { maxVx, maxVy, maxSpin } = board.release
  return {
    x: zone.minX + (zone.maxX - zone.minX) * random(),
    y: zone.y,
    vx: (random() * 2 - 1) * maxVx,
    vy: random() * maxVy,
    angle: random() * TWO_PI,
    angularVelocity: (random() * 2 - 1) * maxSpin
  }
}
