/**
 * How each engine version plays, measured (issue #11's table): the bucket
 * distribution's distance to an ideal Galton board, the edge bucket's
 * probability, the top multiplier and the payout's standard deviation
 * (volatility), the fall, and how closely the calibration pins the RTP,
 * beside the best-known binomial Plinko (Stake's published 16-row high-risk
 * table on Binomial(16, ½)) and the goals.
 *
 *   import { runGameFigures } from './bench/game-figures.js'
 *   await runGameFigures({ quick: false, log: console.log })
 *
 * Fresh drops (nonces 0..N-1 of a bench seed pair, on all cores) measure the
 * distance and the fall; the calibration's own bucket counts (millions of
 * drops, engine/versions/multipliers-*.js) give the rare edge buckets, the
 * volatility and the RTP's confidence interval.
 */
import { ENGINE_VERSIONS, MIN_ROWS, MAX_ROWS, RISKS, createBoard, rtpStatistics, calibrationOf } from '../engine/index.js'
import { simulateBatch } from '../cli/simulate-batch.js'
import { binomialDistribution, totalVariation, edgeProbability } from '../cli/distribution-statistics.js'
import { formatTable, int, fixed } from '../cli/text-table.js'

/** Stake's Plinko, 16 rows, high risk (published table), on Binomial(16, ½): the reference column. */
export const STAKE_16_HIGH = Object.freeze([1000, 130, 26, 9, 4, 2, 0.2, 0.2, 0.2, 0.2, 0.2, 2, 4, 9, 26, 130, 1000])

export const GAME_GOALS = Object.freeze({ tv: 0.10, topMultiplier: 100, sigma16High: 4, fall16: 3.5, fall8: 2, halfWidth: 0.003 })

const SEED = Object.freeze({ serverSeed: 'plinko-bench-game-figures', clientSeed: 'bench' })

/**
 * @param {{ quick?: boolean, log?: (line: string) => void, drops?: number }} [options]
 *   drops: fresh drops per board (default 200,000; --quick 20,000)
 */
export async function runGameFigures ({ quick = false, log = console.log, drops = quick ? 20_000 : 200_000 } = {}) {
  const started = performance.now()
  const figures = {}
  for (const version of ENGINE_VERSIONS) {
    const perRows = {}
    for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
      const fresh = await simulateBatch({ rows, engineVersion: version, drops, ...SEED })
      const calibration = calibrationOf(rows, version)
      const tables = Object.fromEntries(RISKS.map((risk) => [risk, createBoard({ rows, risk, engineVersion: version }).multipliers]))
      const stats = Object.fromEntries(RISKS.map((risk) => [risk, rtpStatistics(calibration.bucketCounts, tables[risk])]))
      perRows[rows] = {
        tv: totalVariation(fresh.counts, binomialDistribution(rows)),
        fall: fresh.meanTicks / 60,
        longest: fresh.maxTicks,
        edge: edgeProbability(calibration.bucketCounts),
        calibrationDrops: calibration.drops,
        top: Object.fromEntries(RISKS.map((risk) => [risk, Math.max(...tables[risk])])),
        sigma: Object.fromEntries(RISKS.map((risk) => [risk, stats[risk].standardError * Math.sqrt(stats[risk].drops)])),
        halfWidth: Object.fromEntries(RISKS.map((risk) => [risk, 1.96 * stats[risk].standardError])),
        rtp: Object.fromEntries(RISKS.map((risk) => [risk, stats[risk].rtp]))
      }
    }
    figures[version] = perRows
  }

  const stake = rtpStatistics(binomialDistribution(16).map((p) => p * 1e12), STAKE_16_HIGH)
  const stakeSigma = stake.standardError * Math.sqrt(stake.drops)
  const worst = (version, pick) => Math.max(...Object.values(figures[version]).map(pick))
  const pct = (x) => `${fixed(x * 100, 2)}%`
  const goal = (ok, text) => `${text}: ${ok ? 'met' : 'not met'}`
  const newest = ENGINE_VERSIONS[ENGINE_VERSIONS.length - 1]
  const f = (version) => figures[version]

  log(`== Game figures: how each engine version plays (${int(drops)} fresh drops per board; edge, volatility and RTP from each version's calibration) ==`)
  log('')
  const rows = [
    ['distance to Binomial(rows, ½) (TV), 8 / 12 / 16 rows', ...ENGINE_VERSIONS.map((v) => `${fixed(f(v)[8].tv, 3)} / ${fixed(f(v)[12].tv, 3)} / ${fixed(f(v)[16].tv, 3)}`), '0', ''],
    ['  worst over 8–16 rows', ...ENGINE_VERSIONS.map((v) => fixed(worst(v, (r) => r.tv), 3)), '0', goal(worst(newest, (r) => r.tv) <= GAME_GOALS.tv, `≤ ${GAME_GOALS.tv}`)],
    ['edge bucket probability, 16 rows (each)', ...ENGINE_VERSIONS.map((v) => f(v)[16].edge.toExponential(2)), binomialDistribution(16)[0].toExponential(2), 'low enough to pay big'],
    ['top multiplier, 16 rows high risk', ...ENGINE_VERSIONS.map((v) => `${f(v)[16].top.high}×`), `${STAKE_16_HIGH[0]}×`, goal(f(newest)[16].top.high >= GAME_GOALS.topMultiplier, `≥ ${GAME_GOALS.topMultiplier}×`)],
    ['payout standard deviation, 16 rows high risk', ...ENGINE_VERSIONS.map((v) => fixed(f(v)[16].sigma.high, 2)), fixed(stakeSigma, 2), goal(f(newest)[16].sigma.high >= GAME_GOALS.sigma16High, `≥ ${GAME_GOALS.sigma16High}`)],
    ['mean fall, 16 rows', ...ENGINE_VERSIONS.map((v) => `${fixed(f(v)[16].fall, 2)} s`), 'about 3 s', goal(f(newest)[16].fall <= GAME_GOALS.fall16, `≤ ${GAME_GOALS.fall16} s`)],
    ['mean fall, 8 rows', ...ENGINE_VERSIONS.map((v) => `${fixed(f(v)[8].fall, 2)} s`), '', goal(f(newest)[8].fall <= GAME_GOALS.fall8, `≤ ${GAME_GOALS.fall8} s`)],
    ['longest fall seen (ticks, any board)', ...ENGINE_VERSIONS.map((v) => int(worst(v, (r) => r.longest))), '', 'within the tick limit'],
    ['RTP 95% CI half-width, worst table', ...ENGINE_VERSIONS.map((v) => pct(worst(v, (r) => Math.max(...Object.values(r.halfWidth))))), '0 (exact)', goal(worst(newest, (r) => Math.max(...Object.values(r.halfWidth))) <= GAME_GOALS.halfWidth, `≤ ${pct(GAME_GOALS.halfWidth)}`)]
  ]
  log(formatTable([{ title: 'figure', align: 'left' }, ...ENGINE_VERSIONS.map((v) => ({ title: `engine ${v}` })), { title: 'Stake (binomial)' }, { title: 'goal (newest)', align: 'left' }], rows))
  log('')
  log('Volatility (payout standard deviation per drop) and top multiplier by board, low / medium / high, newest engine:')
  log(formatTable([{ title: 'rows' }, { title: 'σ low / medium / high' }, { title: 'top ×' }, { title: 'RTP (calibration)' }, { title: '95% CI ±' }, { title: 'calibration drops' }],
    Object.entries(f(newest)).map(([rowCount, r]) => [
      rowCount,
      RISKS.map((risk) => fixed(r.sigma[risk], 2)).join(' / '),
      RISKS.map((risk) => r.top[risk]).join(' / '),
      RISKS.map((risk) => pct(r.rtp[risk])).join(' / '),
      RISKS.map((risk) => pct(r.halfWidth[risk])).join(' / '),
      int(r.calibrationDrops)
    ])))
  log(`(${fixed((performance.now() - started) / 1000, 0)} s; reproduce: npm run bench, or node bench/run.js --only game)`)
  return figures
}
