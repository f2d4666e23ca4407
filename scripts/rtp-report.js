#!/usr/bin/env node
// Independent check of the calibrated tables: simulates fresh drops (a seed
// pair other than calibration's) per row count and prints, per rows × risk,
// the calibrated RTP and the measured RTP with its 95% confidence interval,
// as the markdown table in the README. Usage: node scripts/rtp-report.js [--drops 1000000]
import { simulateBatch } from '../cli/simulate-batch.js'
import { createBoard, MIN_ROWS, MAX_ROWS } from '../engine/board.js'
import { RISKS, CALIBRATION } from '../engine/multipliers.js'
import { rtpStatistics } from '../engine/rtp-statistics.js'

const dropsArg = process.argv.indexOf('--drops')
const drops = dropsArg > 0 ? Number(process.argv[dropsArg + 1]) : 1_000_000
const seeds = { serverSeed: 'plinko-arena-rtp-report-1', clientSeed: 'report' }
const percent = (x) => (x * 100).toFixed(2) + '%'
const lines = [
  `| rows | risk | multipliers (edge … centre) | calibrated RTP (${CALIBRATION.drops.toLocaleString('en')} drops) | measured RTP (${drops.toLocaleString('en')} fresh drops) | 95% CI |`,
  '| --- | --- | --- | --- | --- | --- |'
]
for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
  const result = await simulateBatch({ rows, drops, ...seeds })
  process.stderr.write(`rows ${rows}: ${result.seconds.toFixed(1)} s\n`)
  for (const risk of RISKS) {
    const board = createBoard({ rows, risk })
    const stats = rtpStatistics(result.counts, board.multipliers)
    const half = board.multipliers.slice(0, Math.ceil(board.multipliers.length / 2)).join(' ')
    lines.push(`| ${rows} | ${risk} | ${half} | ${percent(CALIBRATION.rtp[rows][risk])} | ${percent(stats.rtp)} | ${percent(stats.ci95[0])} – ${percent(stats.ci95[1])} |`)
  }
}
process.stdout.write(lines.join('\n') + '\n')
