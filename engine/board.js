import { engineRules, ENGINE_VERSION } from './version.js'

export const MIN_ROWS = 8
export const MAX_ROWS = 16
/** Risk levels, from the flattest multiplier table to the steepest. */
export const RISKS = Object.freeze(['low', 'medium', 'high'])

/**
 * @typedef {{ name: string, density: number, restitution: number, friction: number }} BoardMaterial
 * @typedef {object} Board
 * @property {number} rows @property {'low'|'medium'|'high'} risk
 * @property {string} engineVersion the version whose rules built it
 * @property {number} width @property {number} height
 * @property {number} pegRadius @property {number} ballRadius
 * @property {{x: number, y: number}[]} pegs  row by row, left to right
 * @property {[number, number, number, number][]} walls  segments x1, y1, x2, y2
 * @property {{ minX: number, maxX: number, y: number }} dropZone
 * @property {number} bucketLineY  a ball whose centre passes this line has landed
 * @property {number} bucketLeftX  left edge of bucket 0
 * @property {number} bucketWidth
 * @property {number[]} multipliers  one per bucket, left to right
 * @property {BoardMaterial} ballMaterial @property {BoardMaterial} pegMaterial  pegs and walls
 * @property {{ maxVx: number, maxVy: number, maxSpin: number }} release  bounds of the seeded release
 * @property {number} maxDropTicks  a ball still in play after this many ticks lands where it is
 * @property {object} solver  the solver constants of the version (see solver.js)
 */

/**
 * Builds a Plinko board under one engine version: `rows` rows of pegs in a
 * triangle (row r has r + 3 pegs), slanted side walls tangent to the
 * outermost pegs, and rows + 1 buckets, one per gap of the last row.
 * @param {{ rows: number, risk: string, engineVersion?: string }} options
 *   engineVersion: default the newest (ENGINE_VERSION)
 * @returns {Board}
 * @throws {RangeError} bad rows or risk; UnknownEngineVersionError
 */
export function createBoard ({ rows, risk, engineVersion = ENGINE_VERSION } = {}) {
  return buildBoard(engineRules(engineVersion), rows, risk)
}

/**
 * The board of `rows` and `risk` from a version's rules (engineRules(), or
 * candidate rules while exploring a new version: scripts/explore-board.js).
 * Rules without multiplier tables give a board whose multipliers are all 0.
 * @param {object} rules @param {number} rows @param {string} risk
 * @returns {Board}
 */
export function buildBoard (rules, rows, risk) {
  if (!Number.isInteger(rows) || rows < MIN_ROWS || rows > MAX_ROWS) {
    throw new RangeError(`rows must be an integer from ${MIN_ROWS} to ${MAX_ROWS}`)
  }
  if (!RISKS.includes(risk)) throw new RangeError(`risk must be one of ${RISKS.join(', ')}`)
  const g = rules.geometry
  const s = g.pegSpacing
  const lastRowPegs = rows + 2
  const width = (lastRowPegs - 1) * s + 2 * g.sideMargin
  const centerX = width / 2
  const firstRowY = g.dropHeight + 2 * g.ballRadius
  const lastRowY = firstRowY + (rows - 1) * g.rowSpacing
  const bucketLineY = lastRowY + g.bucketDepth

  const pegs = []
  for (let r = 0; r < rows; r++) {
    const count = r + 3
    const y = firstRowY + r * g.rowSpacing
    for (let k = 0; k < count; k++) pegs.push({ x: centerX + (k - (count - 1) / 2) * s, y })
  }

  // Each side wall runs along the line of outermost pegs, shifted outwards
  // so it is tangent to them: a ball can never sit between wall and peg.
  const run = s / 2 // horizontal shift per row
  const slantLength = Math.sqrt(run * run + g.rowSpacing * g.rowSpacing)
  const shift = g.pegRadius * slantLength / g.rowSpacing // horizontal offset for a perpendicular distance of pegRadius
  const topOuterX = s + shift // distance from centre at the first row
  const bottomOuterX = s + (rows - 1) * run + shift
  const walls = []
  for (const side of [-1, 1]) {
    const xTop = centerX + side * topOuterX
    const xBottom = centerX + side * bottomOuterX
    walls.push([xTop, 0, xTop, firstRowY]) // vertical guide above the pegs
    walls.push([xTop, firstRowY, xBottom, lastRowY]) // slant along the outer pegs
    walls.push([xBottom, lastRowY, xBottom, bucketLineY + g.ballRadius]) // bucket side
  }

  const table = rules.multipliers?.[rows]?.[risk]
  return Object.freeze({
    rows,
    risk,
    engineVersion: rules.version,
    width,
    height: bucketLineY + 3 * g.ballRadius,
    pegRadius: g.pegRadius,
    ballRadius: g.ballRadius,
    pegs,
    walls,
    dropZone: { minX: centerX - g.dropZoneHalfWidth, maxX: centerX + g.dropZoneHalfWidth, y: g.dropHeight },
    bucketLineY,
    bucketLeftX: centerX - (lastRowPegs - 1) / 2 * s,
    bucketWidth: s,
    multipliers: table ? table.slice() : new Array(rows + 1).fill(0),
    ballMaterial: rules.ballMaterial,
    pegMaterial: rules.pegMaterial,
    release: rules.release,
    maxDropTicks: rules.maxDropTicks,
    solver: rules.solver
  })
}

/**
 * Bucket index for a ball that crossed the bucket line at x: the gap of the
 * last row it fell through, clamped to the outer buckets.
 * @param {Board} board @param {number} x
 */
export function bucketAt (board, x) {
  const bucket = Math.floor((x - board.bucketLeftX) / board.bucketWidth)
  return bucket < 0 ? 0 : (bucket > board.rows ? board.rows : bucket)
}

/**
 * The multiplier table of one board under one engine version (a copy).
 * @param {number} rows @param {string} risk @param {string} [engineVersion] default the newest
 */
export function multiplierTable (rows, risk, engineVersion = ENGINE_VERSION) {
  return createBoard({ rows, risk, engineVersion }).multipliers
}
