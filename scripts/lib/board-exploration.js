import { Worker } from 'node:worker_threads'
import { availableParallelism } from 'node:os'
import { binomialDistribution, totalVariation } from '../../cli/distribution-statistics.js'

/**
 * Simulates `drops` drops of candidate `rules` on a board of `rows` rows on
 * all cores and returns bucket counts and tick statistics.
 * @param {object} rules engine rules (engine/versions/*), possibly a candidate
 * @param {number} rows @param {number} drops
 * @param {{ workers?: number, seed?: string }} [options]
 */
export async function exploreBoard (rules, rows, drops, { workers = availableParallelism(), seed = 'explore' } = {}) {
  const threads = Math.max(1, Math.min(workers, drops))
  const parts = await Promise.all(Array.from({ length: threads }, (_, t) => new Promise((resolve, reject) => {
    const worker = new Worker(new URL('./board-exploration-worker.js', import.meta.url), {
      workerData: { rules, rows, seed, from: Math.floor(drops * t / threads), to: Math.floor(drops * (t + 1) / threads) }
    })
    worker.once('message', resolve)
    worker.once('error', reject)
  })))
  const counts = new Array(rows + 1).fill(0)
  const ticks = new Uint32Array(drops)
  let offset = 0
  for (const part of parts) {
    part.counts.forEach((c, i) => { counts[i] += c })
    ticks.set(part.ticks, offset)
    offset += part.ticks.length
  }
  ticks.sort()
  let sum = 0
  for (const t of ticks) sum += t
  return {
    counts,
    tv: totalVariation(counts, binomialDistribution(rows)),
    edge: (counts[0] + counts[rows]) / 2 / drops,
    meanTicks: sum / drops,
    p99Ticks: ticks[Math.floor(drops * 0.99)],
    maxTicks: ticks[drops - 1]
  }
}
