import { RISKS } from '../engine/board.js'
import { rtpStatistics } from '../engine/rtp-statistics.js'

/**
 * Designs the multiplier tables of a new engine version from the bucket
 * distribution its board measures (scripts/calibrate.js). Shipped tables
 * are data in engine/versions/ and never change with this file.
 */

/** The seeds calibration drops are drawn from (nonces 0..drops-1). */
export const CALIBRATION_SEED = Object.freeze({ serverSeed: 'plinko-arena-calibration-2', clientSeed: 'calibration' })
export const TARGET_RTP = 0.99

/**
 * Per risk, the anchors of a table: the multiplier of the centre bucket and
 * of the two edge buckets, the edge growing geometrically from 8 to 16 rows
 * (low 5.6× → 16×, medium 13× → 110×, high 29× → 1,000×, the spans players
 * know from the best-known tables). In between, multipliers rise from the
 * centre to the edge with how unlikely a bucket is (see shapedTable), the
 * curve's exponent solved so the return is TARGET_RTP.
 */
export const RISK_ANCHORS = Object.freeze({
  low: { center: [0.5, 0.5], edge: [5.6, 16] },
  medium: { center: [0.4, 0.3], edge: [13, 110] },
  high: { center: [0.2, 0.2], edge: [29, 1000] }
})

/** Left-right symmetrized bucket probabilities: the board is symmetric, so this halves the noise. */
export function symmetrize (counts) {
  const n = counts.length
  const total = counts.reduce((a, b) => a + b, 0)
  return counts.map((c, i) => (c + counts[n - 1 - i]) / (2 * total))
}

/** @param {number} rows @param {keyof typeof RISK_ANCHORS} risk */
export function anchorsFor (rows, risk) {
  const { center, edge } = RISK_ANCHORS[risk]
  const f = (rows - 8) / 8
  return { center: center[0] + (center[1] - center[0]) * f, edge: edge[0] * Math.pow(edge[1] / edge[0], f) }
}

function expectedReturn (p, m) {
  let sum = 0
  for (let i = 0; i < p.length; i++) sum += p[i] * m[i]
  return sum
}

/**
 * m_i = center + (edge − center) · u_i^β, where u_i = ln(p_center / p_i) /
 * ln(p_center / p_edge) runs from 0 at the centre to 1 at the edges: a
 * larger β keeps more buckets near the centre's multiplier and puts the
 * return in the edges (steeper, more volatile).
 */
function shapedTable (p, { center, edge }, beta) {
  const pCenter = Math.max(...p)
  // A bucket no calibration drop reached (a tiny pilot) is shaped as if half as likely as the rarest one seen.
  const floor = Math.min(...p.filter((pi) => pi > 0)) / 2
  p = p.map((pi) => (pi > 0 ? pi : floor))
  const pEdge = Math.min(p[0], p[p.length - 1])
  const span = Math.log(pCenter / pEdge)
  return p.map((pi) => center + (edge - center) * Math.pow(Math.max(0, Math.log(pCenter / pi) / span), beta))
}

function niceRound (m) {
  if (m >= 100) return Math.round(m / 10) * 10
  if (m >= 10) return Math.round(m)
  if (m >= 1) return Math.round(m * 10) / 10
  return Math.round(m * 100) / 100
}

/**
 * Designs one table for bucket probabilities `p`: shape between the
 * anchors, round to readable values, then nudge symmetric pairs of small
 * multipliers until the return is as close to TARGET_RTP as the grid allows,
 * keeping the table symmetric and never decreasing from the centre outwards.
 * @param {number[]} p @param {number} rows @param {string} risk
 */
export function designTable (p, rows, risk) {
  const anchors = anchorsFor(rows, risk)
  let lo = 0.01
  let hi = 100
  // The return falls as β grows: bisect on a log scale.
  for (let i = 0; i < 200; i++) {
    const mid = Math.sqrt(lo * hi)
    if (expectedReturn(p, shapedTable(p, anchors, mid)) > TARGET_RTP) lo = mid
    else hi = mid
  }
  const table = shapedTable(p, anchors, Math.sqrt(lo * hi)).map(niceRound)
  // Passes in 0.1 on multipliers from 1 to 10, then 0.01 and 0.001 on those
  // below 1 (payouts are computed in thousandths); 10× and more stay round.
  for (const [unit, from, below] of [[0.1, 1, 10], [0.01, 0, 1], [0.001, 0, 1]]) nudge(table, p, unit, from, below)
  return table
}

function nudge (table, p, unit, from, below) {
  const n = table.length
  const half = Math.floor((n - 1) / 2)
  const centerIndex = (n - 1) / 2
  const inward = (i) => (i < centerIndex ? i + 1 : i - 1)
  for (let iteration = 0; iteration < 100000; iteration++) {
    const gap = TARGET_RTP - expectedReturn(p, table)
    let best = null
    for (let i = 0; i <= half; i++) {
      const j = n - 1 - i
      if (table[i] >= below || table[i] < from) continue
      for (const step of [unit, -unit]) {
        const next = Math.round((table[i] + step) * 1000) / 1000
        if (next < 0.1) continue
        // Stay monotone: not below the next bucket inwards, not above the next outwards.
        if (i !== j && next < table[inward(i)]) continue
        if (i > 0 && next > table[i - 1]) continue
        const change = (next - table[i]) * (i === j ? p[i] : p[i] + p[j])
        const remaining = Math.abs(gap - change)
        if (remaining < Math.abs(gap) - 1e-12 && (!best || remaining < best.remaining)) best = { i, j, next, remaining }
      }
    }
    if (!best) break
    table[best.i] = best.next
    table[best.j] = best.next
  }
}

/** @param {Record<number, number[]>} distributions bucket counts per rows */
export function designTables (distributions) {
  const tables = {}
  for (const [rows, counts] of Object.entries(distributions)) {
    const p = symmetrize(counts)
    tables[rows] = {}
    for (const risk of RISKS) tables[rows][risk] = designTable(p, Number(rows), risk)
  }
  return tables
}

/**
 * Source of engine/versions/multipliers-VERSION.js for the designed tables:
 * the tables, and per row count the calibration drops, their bucket counts
 * and each table's RTP, standard deviation per drop and 95% CI half-width
 * on them.
 * @param {{ version: string, tables: object, distributions: Record<number, number[]>, drops: Record<number, number>, seed: { serverSeed: string, clientSeed: string } }} calibration
 */
export function formatMultiplierModule ({ version, tables, distributions, drops, seed }) {
  const lines = []
  lines.push(`// Generated by scripts/calibrate.js for engine ${version}: once shipped, never edit it.`)
  lines.push(`// Calibrated on simulated drops (server seed "${seed.serverSeed}", client seed "${seed.clientSeed}",`)
  lines.push('// nonces 0..drops-1 per row count; the bucket distribution does not depend on risk).')
  lines.push('')
  lines.push('/** Multipliers per rows and risk, left bucket to right. */')
  lines.push('export const MULTIPLIER_TABLES = Object.freeze({')
  for (const rows of Object.keys(tables)) {
    const row = RISKS.map((risk) => `    ${risk}: Object.freeze([${tables[rows][risk].join(', ')}])`).join(',\n')
    lines.push(`  ${rows}: Object.freeze({\n${row}\n  }),`)
  }
  lines.push('})')
  lines.push('')
  lines.push('/** Calibration per row count: drops simulated, bucket counts, and per risk the RTP, its standard deviation per drop and 95% CI half-width. */')
  lines.push('export const CALIBRATION = Object.freeze({')
  lines.push(`  seed: Object.freeze({ serverSeed: ${JSON.stringify(seed.serverSeed)}, clientSeed: ${JSON.stringify(seed.clientSeed)} }),`)
  lines.push(`  drops: Object.freeze({ ${Object.keys(drops).map((rows) => `${rows}: ${drops[rows]}`).join(', ')} }),`)
  lines.push('  bucketCounts: Object.freeze({')
  for (const rows of Object.keys(distributions)) lines.push(`    ${rows}: Object.freeze([${distributions[rows].join(', ')}]),`)
  lines.push('  }),')
  for (const [name, pick, digits] of [['rtp', (s) => s.rtp, 6], ['standardDeviation', (s) => s.standardError * Math.sqrt(s.drops), 4], ['halfWidth95', (s) => 1.96 * s.standardError, 6]]) {
    lines.push(`  ${name}: Object.freeze({`)
    for (const rows of Object.keys(tables)) {
      const parts = RISKS.map((risk) => `${risk}: ${pick(rtpStatistics(distributions[rows], tables[rows][risk])).toFixed(digits)}`)
      lines.push(`    ${rows}: Object.freeze({ ${parts.join(', ')} }),`)
    }
    lines.push('  }),')
  }
  lines.push('})')
  lines.push('')
  return lines.join('\n')
}
