/**
 * Plinko Arena's deterministic physics engine. Pure ESM; its only import is
 * seedrandom. The simulation uses + - * / Math.sqrt, comparisons and integer
 * operations only, so every JavaScript engine computes the same bits.
 */
export { ENGINE_VERSION, ENGINE_VERSIONS, engineRules, isEngineVersion, UnknownEngineVersionError } from './version.js'
export { World, DEFAULT_TIMESTEP, DEFAULT_GRAVITY, DEFAULT_CELL_SIZE } from './world.js'
export { BODY_STRIDE, BODY_X, BODY_Y, BODY_ANGLE } from './body-layout.js'
export { FixedTimestep } from './fixed-timestep.js'
export { SpatialHash } from './spatial-hash.js'
export { StaticGrid } from './static-grid.js'
export { StateHasher } from './state-hasher.js'
export { METAL, HARD_PLASTIC } from './materials.js'
export { createBoard, buildBoard, bucketAt, multiplierTable, MIN_ROWS, MAX_ROWS, RISKS } from './board.js'
export { SOLVER } from './solver.js'
export { dropInitialConditions } from './drop-initial-conditions.js'
export { DropSimulator, simulateDrop } from './drop-simulator.js'
export { sha256Hex, hmacSha256Hex, deriveDropSeed, dropSeedMessage } from './fairness.js'
export { verifyDrop } from './verify-drop.js'
export { rtpStatistics } from './rtp-statistics.js'
export { calibrationOf } from './calibration.js'
