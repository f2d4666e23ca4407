#!/usr/bin/env node
// Calibrates the multiplier tables of a new engine version by simulation and
// writes engine/versions/multipliers-VERSION.js:
//
//   node scripts/calibrate.js --engine-version 2.0.0 [--pilot 1000000] [--half-width 0.0028] [--max-drops 80000000]
//
// Per row count: a pilot of --pilot drops designs the tables (cli/table-design.js);
// the most volatile table's standard deviation σ then sets how many drops pin
// every table's RTP down to ±half-width at 95% (1.96·σ/√N), and the drops are
// simulated up to that count (nonces 0..N-1 of the calibration seed); the
// tables are designed again on all of them. A version that already has tables
// is refused (a shipped version is never recalibrated) unless --force.
import { writeFileSync } from 'node:fs'
import { parseArgs } from 'node:util'
import { simulateBatch } from '../cli/simulate-batch.js'
import { designTables, formatMultiplierModule, CALIBRATION_SEED } from '../cli/table-design.js'
import { MIN_ROWS, MAX_ROWS, RISKS } from '../engine/board.js'
import { engineRules } from '../engine/version.js'
import { rtpStatistics } from '../engine/rtp-statistics.js'

const { values } = parseArgs({
  options: {
    'engine-version': { type: 'string' },
    pilot: { type: 'string', default: '1000000' },
    'half-width': { type: 'string', default: '0.0028' },
    'max-drops': { type: 'string', default: '80000000' },
    force: { type: 'boolean' }
  }
})
const version = values['engine-version']
if (!version) {
  console.error('usage: node scripts/calibrate.js --engine-version V [--pilot N] [--half-width H] [--max-drops N] [--force]')
  process.exit(2)
}
if (engineRules(version).multipliers && !values.force) {
  console.error(`engine ${version} already has multiplier tables: a shipped version is never recalibrated (--force to redo an unshipped one)`)
  process.exit(2)
}
const pilot = Number(values.pilot)
const halfWidth = Number(values['half-width'])
const maxDrops = Number(values['max-drops'])

const distributions = {}
const drops = {}
for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
  const first = await simulateBatch({ rows, engineVersion: version, drops: pilot, ...CALIBRATION_SEED })
  const pilotTables = designTables({ [rows]: first.counts })[rows]
  const sigma = Math.max(...RISKS.map((risk) => {
    const s = rtpStatistics(first.counts, pilotTables[risk])
    return s.standardError * Math.sqrt(s.drops)
  }))
  const needed = Math.min(maxDrops, Math.max(pilot, Math.ceil((1.96 * sigma / halfWidth) ** 2)))
  const rest = needed > pilot ? await simulateBatch({ rows, engineVersion: version, firstNonce: pilot, drops: needed - pilot, ...CALIBRATION_SEED }) : null
  distributions[rows] = first.counts.map((c, i) => c + (rest ? rest.counts[i] : 0))
  drops[rows] = needed
  const maxTicks = Math.max(first.maxTicks, rest?.maxTicks ?? 0)
  process.stderr.write(`rows ${rows}: σ ${sigma.toFixed(2)} in the pilot → ${needed} drops in ${(first.seconds + (rest?.seconds ?? 0)).toFixed(0)} s, longest ${maxTicks} ticks\n`)
}
const tables = designTables(distributions)
const target = new URL(`../engine/versions/multipliers-${version}.js`, import.meta.url)
writeFileSync(target, formatMultiplierModule({ version, tables, distributions, drops, seed: CALIBRATION_SEED }))
process.stderr.write(`wrote ${target.pathname}\n`)
