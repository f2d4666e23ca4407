#!/usr/bin/env node
// Explores candidate board geometries and materials for a new engine version
// with the fast simulator, and prints how each plays: distance of its bucket
// distribution to Binomial(rows, ½), the weight of its tails, and its fall.
//
//   node scripts/explore-board.js [--drops 20000] [--rows 16,8] [--grid '{"pegSpacing":[12,14],...}'] [--json]
//
// Each grid axis lists values to try (every combination is run):
//   pegSpacing (px), pegRadius and ballRadius as fractions (pegRadius of the
//   spacing, ballRadius of half the gap between two pegs), rowSpacing as a
//   fraction of the spacing, restitution (ball and pegs alike), and friction
//   as [ball, peg] pairs (contacts mix them as their geometric mean).
// With more than one candidate, a 1,000-drop pilot on 16 rows discards those
// far off (TV > 0.15 or a fall over 4 s) before the full runs on --rows.
import { parseArgs } from 'node:util'
import { engineRules } from '../engine/version.js'
import { exploreBoard } from './lib/board-exploration.js'
import { tailRatio } from '../cli/distribution-statistics.js'

const { values } = parseArgs({
  options: { drops: { type: 'string', default: '20000' }, rows: { type: 'string', default: '16,8' }, grid: { type: 'string' }, base: { type: 'string', default: '1.0.0' }, json: { type: 'boolean' } }
})
const drops = Number(values.drops)
const rowCounts = values.rows.split(',').map(Number)
const grid = {
  pegSpacing: [10, 12, 14],
  pegRadius: [0.15, 0.2, 0.25],
  ballRadius: [0.5, 0.6, 0.7, 0.8],
  rowSpacing: [0.866, 1],
  restitution: [0.3, 0.35, 0.4],
  friction: [[0.1, 0.1], [0.2, 0.2], [0.3, 0.3]],
  ...(values.grid ? JSON.parse(values.grid) : {})
}

/** Candidate rules: the base version's, with this geometry and these materials. */
function candidateRules (base, { pegSpacing, pegRadius, ballRadius, rowSpacing, restitution, friction }) {
  const s = pegSpacing
  const p = Math.round(s * pegRadius * 4) / 4
  const r = Math.round(ballRadius * (s - 2 * p) / 2 * 4) / 4
  const h = Math.round(s * rowSpacing * 4) / 4
  return {
    ...base,
    multipliers: null,
    geometry: { ...base.geometry, pegSpacing: s, pegRadius: p, ballRadius: r, rowSpacing: h, sideMargin: s, dropHeight: h, dropZoneHalfWidth: s / 4, bucketDepth: Math.round(s * 0.6) },
    release: { ...base.release, maxVx: Math.round(20 * s / 36), maxVy: Math.round(20 * s / 36) },
    ballMaterial: { ...base.ballMaterial, restitution, friction: friction[0] },
    pegMaterial: { ...base.pegMaterial, restitution, friction: friction[1] }
  }
}

function* combinations (axes) {
  const keys = Object.keys(axes)
  const index = keys.map(() => 0)
  for (;;) {
    yield Object.fromEntries(keys.map((k, i) => [k, axes[k][index[i]]]))
    let i = keys.length - 1
    while (i >= 0 && ++index[i] === axes[keys[i]].length) index[i--] = 0
    if (i < 0) return
  }
}

const base = engineRules(values.base)
const points = [...combinations(grid)]
const results = []
for (const point of points) {
  const rules = candidateRules(base, point)
  const g = rules.geometry
  const label = `s ${g.pegSpacing} peg ${g.pegRadius} ball ${g.ballRadius} row ${g.rowSpacing} e ${point.restitution} μ ${point.friction.join('/')}`
  if (!(2 * g.ballRadius < g.pegSpacing - 2 * g.pegRadius)) continue
  if (points.length > 1) {
    const pilot = await exploreBoard(rules, 16, 1000)
    if (pilot.tv > 0.15 || pilot.meanTicks > 240) {
      process.stderr.write(`${label}: pilot TV ${pilot.tv.toFixed(3)}, fall ${(pilot.meanTicks / 60).toFixed(2)} s: skipped\n`)
      continue
    }
  }
  const byRows = {}
  for (const rows of rowCounts) {
    const r = await exploreBoard(rules, rows, drops)
    byRows[rows] = { tv: r.tv, tail: tailRatio(r.counts), fall: r.meanTicks / 60, longest: r.maxTicks, counts: r.counts }
  }
  const worstTv = Math.max(...rowCounts.map((rows) => byRows[rows].tv))
  results.push({ point, geometry: g, byRows, worstTv })
  process.stderr.write(`${label}: ${rowCounts.map((rows) => `${rows} rows TV ${byRows[rows].tv.toFixed(3)} tails ×${byRows[rows].tail.toFixed(1)} fall ${byRows[rows].fall.toFixed(2)} s`).join('; ')}\n`)
}
results.sort((a, b) => a.worstTv - b.worstTv)
if (values.json) {
  process.stdout.write(JSON.stringify(results) + '\n')
} else {
  process.stdout.write(`${drops} drops per board; TV: total-variation distance to Binomial(rows, ½); tails: share of the 3 outer buckets each side over the binomial's\n\n`)
  process.stdout.write(`| spacing | peg r | ball r | row | e | μ ball/peg | ${rowCounts.map((r) => `${r} rows: TV, tails, fall`).join(' | ')} | longest |\n`)
  process.stdout.write(`|${'---|'.repeat(7 + rowCounts.length)}\n`)
  for (const { point, geometry: g, byRows } of results) {
    const cells = rowCounts.map((rows) => `${byRows[rows].tv.toFixed(3)}, ×${byRows[rows].tail.toFixed(2)}, ${byRows[rows].fall.toFixed(2)} s`)
    process.stdout.write(`| ${g.pegSpacing} | ${g.pegRadius} | ${g.ballRadius} | ${g.rowSpacing} | ${point.restitution} | ${point.friction.join('/')} | ${cells.join(' | ')} | ${Math.max(...rowCounts.map((rows) => byRows[rows].longest))} |\n`)
  }
}
