/**
 * Version of everything that can change the outcome of a drop: physics
 * constants, solver, board geometry, initial-condition derivation and
 * multiplier tables. Bump it with any such change; stored drops keep the
 * version they were decided under.
 */
export const ENGINE_VERSION = '1.0.0'
