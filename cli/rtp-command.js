import { randomBytes } from 'node:crypto'
import { statSync, writeFileSync } from 'node:fs'
import { availableParallelism } from 'node:os'
import path from 'node:path'
import { createBoard } from '../engine/board.js'
import { rtpStatistics } from '../engine/rtp-statistics.js'
import { calibrationOf } from '../engine/calibration.js'
import { simulateBatch } from './simulate-batch.js'
import { ProgressBar } from './progress-bar.js'
import { distributionChartSvg } from './distribution-chart.js'
import { symmetrize } from './table-design.js'
import { parseOptions, integerOption, rowsOption, riskOption, engineVersionOption, SEED_AND_BOARD_OPTIONS, BOARD_OPTIONS_HELP } from './options.js'
import { UsageError } from './usage-error.js'

export const rtpUsage = 'plinko rtp [--rows 16] [--risk medium] [--engine-version V] [--drops 1000000] [--server-seed S] [--client-seed C] [--workers N] [--chart FILE.svg] [--json]'

export const rtpHelp = `usage: ${rtpUsage}

Simulates nonces 0..drops-1 of one seed pair on every core, prints the bucket
distribution beside the calibrated one and the return to player with its 95%
confidence interval.

${BOARD_OPTIONS_HELP}
  --drops N            drops to simulate, 1 to 1e9 (default 1000000)
  --server-seed S      server seed (default: 32 random bytes, printed)
  --client-seed C      client seed (default "rtp")
  --workers N          worker threads, 1 to 256 (default: one per core)
  --chart FILE.svg     also draw the distribution as an SVG chart into FILE
                       (nothing is written without it); its folder must exist
  --json               print one JSON object instead of the table
  -h, --help           this help`

const OPTIONS = {
  ...SEED_AND_BOARD_OPTIONS,
  drops: { type: 'string' },
  workers: { type: 'string' },
  chart: { type: 'string' },
  json: { type: 'boolean' }
}

/**
 * Simulates many drops (nonces 0..drops-1 of one server/client seed pair),
 * prints the bucket distribution and the return to player with its 95%
 * confidence interval, and writes the distribution as an SVG chart where
 * --chart says (and only then).
 */
export async function rtpCommand (argv, out, err) {
  const options = parseOptions(argv, OPTIONS)
  if (options.help) {
    out.write(rtpHelp + '\n')
    return
  }
  const rows = rowsOption(options.rows)
  const risk = riskOption(options.risk)
  const drops = integerOption(options.drops ?? '1000000', 'drops', { min: 1, max: 1e9 })
  const workers = integerOption(options.workers ?? String(availableParallelism()), 'workers', { min: 1, max: 256 })
  const serverSeed = options['server-seed'] || randomBytes(32).toString('hex')
  const clientSeed = options['client-seed'] ?? 'rtp'
  const chartPath = options.chart === undefined ? null : chartFile(options.chart)
  const engineVersion = engineVersionOption(options['engine-version'])
  const board = createBoard({ rows, risk, engineVersion })
  const calibration = calibrationOf(rows, engineVersion)

  const progress = new ProgressBar(drops, err, `simulating ${rows} rows`)
  const result = await simulateBatch({ rows, engineVersion, drops, serverSeed, clientSeed, workers, onProgress: (done) => progress.update(done) })
  progress.finish()

  const stats = rtpStatistics(result.counts, board.multipliers)
  const calibratedCounts = calibration?.bucketCounts
  const expected = calibratedCounts ? symmetrize(calibratedCounts) : undefined
  if (chartPath) {
    writeFileSync(chartPath, distributionChartSvg({
      title: `Plinko ${rows} rows, ${risk} risk: ${drops} drops, RTP ${(stats.rtp * 100).toFixed(3)}%`,
      counts: result.counts,
      multipliers: board.multipliers,
      expected
    }))
  }

  const summary = {
    engineVersion,
    rows,
    risk,
    drops,
    serverSeed,
    clientSeed,
    counts: result.counts,
    multipliers: board.multipliers,
    rtp: stats.rtp,
    standardError: stats.standardError,
    ci95: stats.ci95,
    calibratedRtp: calibration?.rtp[risk],
    meanTicks: result.meanTicks,
    maxTicks: result.maxTicks,
    seconds: result.seconds,
    dropsPerSecond: drops / result.seconds,
    workers,
    chart: chartPath
  }
  if (options.json) {
    out.write(JSON.stringify(summary) + '\n')
    return
  }
  const percent = (x) => (x * 100).toFixed(3) + '%'
  const lines = []
  lines.push(`engine ${engineVersion} · ${rows} rows · ${risk} risk · ${drops} drops · server seed ${serverSeed} · client seed ${clientSeed}`)
  lines.push('')
  lines.push('bucket  multiplier       drops     share  calibrated')
  result.counts.forEach((count, i) => {
    lines.push(`${String(i).padStart(6)}  ${String(board.multipliers[i]).padStart(10)}  ${String(count).padStart(10)}  ${percent(count / drops).padStart(8)}  ${expected ? percent(expected[i]).padStart(10) : ''}`)
  })
  lines.push('')
  lines.push(`RTP ${percent(stats.rtp)} (95% CI ${percent(stats.ci95[0])} – ${percent(stats.ci95[1])}, standard error ${percent(stats.standardError)})`)
  if (summary.calibratedRtp !== undefined) lines.push(`calibrated RTP ${percent(summary.calibratedRtp)} on ${calibration.drops} calibration drops`)
  lines.push(`${result.seconds.toFixed(1)} s on ${workers} worker(s): ${Math.round(summary.dropsPerSecond)} drops/s, mean ${result.meanTicks.toFixed(1)} ticks (${(result.meanTicks / 60).toFixed(2)} s) per drop, longest ${result.maxTicks}`)
  lines.push(chartPath ? `chart written to ${chartPath}` : 'no chart written (--chart FILE.svg draws one)')
  out.write(lines.join('\n') + '\n')
}

/**
 * --chart FILE: an absolute path, checked before the simulation (which may
 * take minutes) so a typo fails at once: its folder must exist, and FILE
 * must not be a folder.
 * @param {string} file @returns {string}
 */
function chartFile (file) {
  const resolved = path.resolve(file)
  const folder = statSync(path.dirname(resolved), { throwIfNoEntry: false })
  if (!folder?.isDirectory()) throw new UsageError(`--chart ${file}: the folder ${path.dirname(resolved)} does not exist`)
  if (statSync(resolved, { throwIfNoEntry: false })?.isDirectory()) throw new UsageError(`--chart ${file} is a folder: give a file name, e.g. ${path.join(file, 'rtp.svg')}`)
  return resolved
}
