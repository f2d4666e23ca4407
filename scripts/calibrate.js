#!/usr/bin/env node
// Calibrates the multiplier tables by simulation and rewrites
// engine/multipliers.js. Usage: node scripts/calibrate.js [--drops 2000000]
import { writeFileSync } from 'node:fs'
import { simulateBatch } from '../cli/simulate-batch.js'
import { designTables, formatMultiplierModule, CALIBRATION_SEED } from '../cli/calibration.js'
import { MIN_ROWS, MAX_ROWS } from '../engine/board.js'

const dropsArg = process.argv.indexOf('--drops')
const drops = dropsArg > 0 ? Number(process.argv[dropsArg + 1]) : 2_000_000
const distributions = {}
for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
  const result = await simulateBatch({ rows, drops, ...CALIBRATION_SEED })
  distributions[rows] = result.counts
  process.stderr.write(`rows ${rows}: ${drops} drops in ${result.seconds.toFixed(1)} s, mean ${result.meanTicks.toFixed(1)} ticks, max ${result.maxTicks}\n`)
}
const tables = designTables(distributions)
const target = new URL('../engine/multipliers.js', import.meta.url)
writeFileSync(target, formatMultiplierModule(tables, distributions, drops))
writeFileSync(new URL('../.tmp/calibration.json', import.meta.url), JSON.stringify({ drops, distributions, tables }, null, 1))
process.stderr.write('wrote engine/multipliers.js\n')
