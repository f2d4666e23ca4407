#!/usr/bin/env node
// Draws one board's bucket distribution under an engine version, from the
// drops its tables were calibrated on, against Binomial(rows, ½) (an ideal
// Galton board) and the first version's, on a log scale (the tails are
// where boards differ):
//
//   node scripts/distribution-chart.js [--engine-version V] [--rows 16] [--out docs/distribution-16-rows.svg]
import { writeFileSync } from 'node:fs'
import { parseArgs } from 'node:util'
import { distributionChartSvg } from '../cli/distribution-chart.js'
import { binomialDistribution } from '../cli/distribution-statistics.js'
import { createBoard } from '../engine/board.js'
import { calibrationOf } from '../engine/calibration.js'
import { ENGINE_VERSION, ENGINE_VERSIONS } from '../engine/version.js'

const { values } = parseArgs({ options: { 'engine-version': { type: 'string', default: ENGINE_VERSION }, rows: { type: 'string', default: '16' }, out: { type: 'string' } } })
const version = values['engine-version']
const rows = Number(values.rows)
const out = values.out ?? `docs/distribution-${rows}-rows.svg`
const { bucketCounts, drops } = calibrationOf(rows, version)
const first = ENGINE_VERSIONS[0]
const shares = (counts) => { const n = counts.reduce((a, b) => a + b, 0); return counts.map((c) => c / n) }
writeFileSync(out, distributionChartSvg({
  title: `${rows} rows, engine ${version}: ${drops.toLocaleString('en')} drops against Binomial(${rows}, ½) (log scale)`,
  counts: [...bucketCounts],
  multipliers: createBoard({ rows, risk: 'high', engineVersion: version }).multipliers,
  barLabel: `engine ${version}`,
  markers: [
    { label: `Binomial(${rows}, ½)`, shares: binomialDistribution(rows), color: '#d04a4a' },
    ...(first === version ? [] : [{ label: `engine ${first}`, shares: shares(calibrationOf(rows, first).bucketCounts), color: '#999' }])
  ],
  logScale: true
}))
console.log(`wrote ${out}`)
