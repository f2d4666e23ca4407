import { MULTIPLIER_TABLES, CALIBRATION } from './multipliers-2.0.0.js'

/**
 * Engine 2.0.0: a board that plays like a Galton board. Chosen with
 * scripts/explore-board.js (the README's "The board" says why each constant
 * is what it is). Same solver as 1.0.0; new geometry, peg restitution,
 * release and multiplier tables. A shipped version is never edited
 * (tests/engine/fixtures/engine-2.0.0.json keeps it honest).
 */
export const ENGINE_2_0_0 = {
  version: '2.0.0',
  solver: { gravity: 980, timestep: 1 / 60, restitutionThreshold: 30, linearSlop: 0.05, correctionFraction: 0.8, maxTravelPerSubstep: 1, maxSubsteps: 16, maxImpactsPerSubstep: 4 },
  /**
   * Board geometry (px; 100 px = 1 m). A near-equilateral lattice of pegs
   * 8 cm apart (rows 7 cm apart), pegs 2.5 cm and the ball 4 cm across:
   * the gap between two pegs of a row is 5.5 cm, so the ball always passes
   * (never wedges) but never flies across a row: each row it meets the one
   * peg below it and goes left or right of it, as in an ideal Galton board.
   */
  geometry: {
    pegRadius: 1.25,
    ballRadius: 2,
    pegSpacing: 8,
    rowSpacing: 7,
    sideMargin: 8,
    dropHeight: 7,
    dropZoneHalfWidth: 2,
    bucketDepth: 5
  },
  /** The same steel ball as 1.0.0; hard-plastic pegs and walls at restitution 0.4 (1.0.0: 0.45), μ 0.3. */
  ballMaterial: { name: 'metal', density: 7.8, restitution: 0.4, friction: 0.2 },
  pegMaterial: { name: 'hard-plastic', density: 1.2, restitution: 0.4, friction: 0.3 },
  /** Release: sideways and downward speed up to 4 px/s, spin up to 3 rad/s either way. */
  release: { maxVx: 4, maxVy: 4, maxSpin: 3 },
  maxDropTicks: 3600,
  multipliers: MULTIPLIER_TABLES,
  calibration: CALIBRATION
}
