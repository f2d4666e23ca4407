import { MULTIPLIER_TABLES, CALIBRATION } from './multipliers-1.0.0.js'

/**
 * Engine 1.0.0, shipped 2026-11: everything besides the shared solver that
 * decides a drop's outcome under this version. A shipped version is never
 * edited: drops recorded under it must re-simulate bit for bit for as long
 * as the ledger keeps them (tests/engine/fixtures/engine-1.0.0.json).
 */
export const ENGINE_1_0_0 = {
  version: '1.0.0',
  /** The solver this version was decided with (checked against the engine's, see solver.js). */
  solver: { gravity: 980, timestep: 1 / 60, restitutionThreshold: 30, linearSlop: 0.05, correctionFraction: 0.8, maxTravelPerSubstep: 1, maxSubsteps: 16, maxImpactsPerSubstep: 4 },
  /**
   * Board geometry (px). The ball is 14 px across and the gap between two
   * pegs of a row is pegSpacing - 2·pegRadius = 28 px, so a ball can never
   * wedge between them.
   */
  geometry: {
    pegRadius: 4,
    ballRadius: 7,
    pegSpacing: 36,
    rowSpacing: 32,
    /** margin from the board's edge to the widest peg row */
    sideMargin: 24,
    /** height above the first peg row where balls are released */
    dropHeight: 32,
    /** half-width of the zone around the centre where a ball may be released */
    dropZoneHalfWidth: 9,
    /** the ball settles in a bucket once its centre passes this far below the last row */
    bucketDepth: 20
  },
  /** A steel ball (restitution 0.4, μ 0.2) on hard-plastic pegs and walls (0.45, μ 0.3). */
  ballMaterial: { name: 'metal', density: 7.8, restitution: 0.4, friction: 0.2 },
  pegMaterial: { name: 'hard-plastic', density: 1.2, restitution: 0.45, friction: 0.3 },
  /** Release: sideways and downward speed up to 20 px/s, spin up to 3 rad/s either way. */
  release: { maxVx: 20, maxVy: 20, maxSpin: 3 },
  /** A ball still in play after this many ticks (60 s) lands where it is. */
  maxDropTicks: 3600,
  multipliers: MULTIPLIER_TABLES,
  calibration: CALIBRATION
}
