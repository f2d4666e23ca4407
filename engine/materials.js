/**
 * Surface materials. Values are chosen for a steel ball on hard plastic
 * (ABS/polycarbonate) pegs and side walls:
 * - hard plastic is stiff but not elastic like steel on steel: a steel ball
 *   dropped on ABS/polycarbonate rebounds with a coefficient of restitution
 *   of roughly 0.4-0.5 at the 1-10 m/s a Plinko ball reaches (we take 0.45
 *   for the plastic and 0.4 for the ball, so contacts use 0.45);
 * - dry steel on plastic has a kinetic friction coefficient of roughly
 *   0.2-0.3 (0.2 and 0.3 here, mixed to ≈0.245);
 * - steel is dense (7.8 g/cm³) and ABS light (about 1.2 g/cm³); density sets
 *   a ball's mass and moment of inertia (solid disc), which matter when balls
 *   collide with each other and for how friction spins them.
 * Mixing follows Box2D: restitution takes the larger value (a bouncy surface
 * stays bouncy), friction the geometric mean (a slippery surface stays
 * slippery).
 */

/** @typedef {{ name: string, density: number, restitution: number, friction: number }} Material */

/** @type {Material} */
export const METAL = Object.freeze({ name: 'metal', density: 7.8, restitution: 0.4, friction: 0.2 })

/** @type {Material} */
export const HARD_PLASTIC = Object.freeze({ name: 'hard-plastic', density: 1.2, restitution: 0.45, friction: 0.3 })

/** @param {number} a @param {number} b */
export function mixRestitution (a, b) {
  return a > b ? a : b
}

/** @param {number} a @param {number} b */
export function mixFriction (a, b) {
  return Math.sqrt(a * b)
}
