import { Worker } from 'node:worker_threads'
import { availableParallelism } from 'node:os'

/**
 * Simulates drops for nonces firstNonce..firstNonce+drops-1 on `workers` threads and returns the
 * bucket counts (the bucket distribution does not depend on risk).
 * @param {object} options
 * @param {number} options.rows @param {number} options.drops
 * @param {string} [options.engineVersion] default the newest
 * @param {number} [options.firstNonce] default 0
 * @param {string} options.serverSeed @param {string} options.clientSeed
 * @param {number} [options.workers]
 * @param {(done: number) => void} [options.onProgress] drops finished so far
 * @returns {Promise<{ counts: number[], drops: number, meanTicks: number, maxTicks: number, seconds: number }>}
 */
export async function simulateBatch ({ rows, engineVersion, firstNonce = 0, drops, serverSeed, clientSeed, workers = availableParallelism(), onProgress }) {
  const started = performance.now()
  const threads = Math.max(1, Math.min(workers, drops))
  const counts = new Array(rows + 1).fill(0)
  let ticks = 0
  let maxTicks = 0
  let done = 0
  const progressEvery = Math.max(1, Math.min(10000, Math.floor(drops / threads / 20)))
  const jobs = []
  for (let t = 0; t < threads; t++) {
    const from = firstNonce + Math.floor(drops * t / threads)
    const to = firstNonce + Math.floor(drops * (t + 1) / threads)
    jobs.push(new Promise((resolve, reject) => {
      const worker = new Worker(new URL('./batch-worker.js', import.meta.url), {
        workerData: { rows, engineVersion, serverSeed, clientSeed, from, to, progressEvery }
      })
      worker.on('message', (message) => {
        if (message.type === 'progress') {
          done += message.done
          onProgress?.(done)
        } else {
          message.counts.forEach((c, i) => { counts[i] += c })
          ticks += message.ticks
          if (message.maxTicks > maxTicks) maxTicks = message.maxTicks
          resolve()
        }
      })
      worker.on('error', reject)
      worker.on('exit', (code) => { if (code !== 0) reject(new Error(`simulation worker exited with code ${code}`)) })
    }))
  }
  await Promise.all(jobs)
  return { counts, drops, meanTicks: ticks / drops, maxTicks, seconds: (performance.now() - started) / 1000 }
}
