import { DEFAULT_GRAVITY, DEFAULT_TIMESTEP, MAX_TRAVEL_PER_SUBSTEP, MAX_SUBSTEPS, MAX_IMPACTS_PER_SUBSTEP } from './world.js'
import { RESTITUTION_THRESHOLD, LINEAR_SLOP, CORRECTION_FRACTION } from './contact-solver.js'

/**
 * The constants of the solver this engine runs (world.js, contact-solver.js).
 * Each engine version names the solver it was decided with; a board whose
 * version needs another solver is refused rather than simulated wrongly, so
 * a future solver change must keep the old solver selectable, not replace it.
 */
export const SOLVER = Object.freeze({
  gravity: DEFAULT_GRAVITY,
  timestep: DEFAULT_TIMESTEP,
  restitutionThreshold: RESTITUTION_THRESHOLD,
  linearSlop: LINEAR_SLOP,
  correctionFraction: CORRECTION_FRACTION,
  maxTravelPerSubstep: MAX_TRAVEL_PER_SUBSTEP,
  maxSubsteps: MAX_SUBSTEPS,
  maxImpactsPerSubstep: MAX_IMPACTS_PER_SUBSTEP
})

/**
 * Throws unless `solver` (a version's) is exactly the one this engine runs.
 * @param {Record<string, number>} solver @param {string} version
 */
export function assertSolver (solver, version) {
  const keys = Object.keys(SOLVER)
  for (const key of keys) {
    if (solver?.[key] !== SOLVER[key]) {
      throw new Error(`engine ${version} needs solver ${key} = ${solver?.[key]}, this engine runs ${SOLVER[key]}`)
    }
  }
  if (Object.keys(solver).length !== keys.length) throw new Error(`engine ${version} names solver constants this engine does not have`)
}
