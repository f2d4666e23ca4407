#!/usr/bin/env node
// Independent check of an engine version's calibrated tables: simulates fresh
// drops (a seed pair other than calibration's) per row count and prints, per
// rows × risk, the calibrated RTP and the measured RTP with its 95%
// confidence interval, as the markdown table in the README.
//
//   node scripts/rtp-report.js --engine-version 2.0.0 [--drops N]
//
// --drops: fresh drops per row count (default: as many as its calibration had,
// so each table's interval is about as narrow as the calibration's).
import { parseArgs } from 'node:util'
import { simulateBatch } from '../cli/simulate-batch.js'
import { binomialDistribution, totalVariation } from '../cli/distribution-statistics.js'
import { createBoard, MIN_ROWS, MAX_ROWS, RISKS } from '../engine/board.js'
import { calibrationOf } from '../engine/calibration.js'
import { ENGINE_VERSION } from '../engine/version.js'
import { rtpStatistics } from '../engine/rtp-statistics.js'

const { values } = parseArgs({ options: { 'engine-version': { type: 'string', default: ENGINE_VERSION }, drops: { type: 'string' } } })
const version = values['engine-version']
const seeds = { serverSeed: 'plinko-arena-rtp-report-2', clientSeed: 'report' }
const percent = (x) => (x * 100).toFixed(2) + '%'
const lines = [
  '| rows | risk | multipliers (edge … centre) | σ per drop | calibration drops | calibrated RTP | fresh drops | measured RTP | 95% CI |',
  '| --- | --- | --- | --- | --- | --- | --- | --- | --- |'
]
for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
  const calibration = calibrationOf(rows, version)
  const drops = values.drops ? Number(values.drops) : calibration.drops
  const result = await simulateBatch({ rows, engineVersion: version, drops, ...seeds })
  process.stderr.write(`rows ${rows}: ${drops} drops in ${result.seconds.toFixed(1)} s, TV ${totalVariation(result.counts, binomialDistribution(rows)).toFixed(4)}, longest ${result.maxTicks} ticks\n`)
  for (const risk of RISKS) {
    const board = createBoard({ rows, risk, engineVersion: version })
    const stats = rtpStatistics(result.counts, board.multipliers)
    const calibrated = rtpStatistics(calibration.bucketCounts, board.multipliers)
    const sigma = stats.standardError * Math.sqrt(stats.drops)
    const half = board.multipliers.slice(0, Math.ceil(board.multipliers.length / 2)).join(' ')
    lines.push(`| ${rows} | ${risk} | ${half} | ${sigma.toFixed(2)} | ${calibration.drops.toLocaleString('en')} | ${percent(calibrated.rtp)} ± ${percent(1.96 * calibrated.standardError)} | ${drops.toLocaleString('en')} | ${percent(stats.rtp)} | ${percent(stats.ci95[0])} – ${percent(stats.ci95[1])} |`)
  }
}
process.stdout.write(lines.join('\n') + '\n')
