/**
 * Where a body's state lives in World.state: BODY_STRIDE doubles per body
 * id, one body after another, so a step reads and writes one block per
 * body (an array of structs) rather than one element of each of a dozen
 * arrays. Hot loops copy these offsets into locals: a module constant read
 * inside a loop costs a check every time.
 */
export const BODY_STRIDE = 16
export const BODY_X = 0
export const BODY_Y = 1
export const BODY_VX = 2
export const BODY_VY = 3
export const BODY_ANGLE = 4
export const BODY_SPIN = 5
export const BODY_PREVIOUS_X = 6
export const BODY_PREVIOUS_Y = 7
export const BODY_PREVIOUS_ANGLE = 8
export const BODY_RADIUS = 9
export const BODY_INVERSE_MASS = 10
export const BODY_INVERSE_INERTIA = 11
export const BODY_RESTITUTION = 12
export const BODY_FRICTION = 13
/** 1 while the body exists, 0 once destroyed (and for ids never used). */
export const BODY_ALIVE = 14
