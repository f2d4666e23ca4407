/**
 * Timing and heap measurement for the benchmarks. Nothing here judges a
 * figure: it measures and returns numbers for the tables.
 */
import { PerformanceObserver } from 'node:perf_hooks'
import v8 from 'node:v8'
import vm from 'node:vm'

/**
 * Steps every scene for `warmup` steps (untimed, for the JIT and the release
 * ramp), then `steps` timed steps each, in round-robin blocks of `block`
 * steps so that a disturbance of the machine (another process, a turbo
 * change) falls on all engines alike. Between blocks, when `gc` is given,
 * garbage is collected untimed, so one engine's garbage is never collected
 * during another engine's block.
 * @param {{ step: () => void }[]} scenes
 * @param {{ warmup: number, steps: number, block: number, gc?: (() => void) | null }} options
 * @returns {Float64Array[]} per scene, the duration of each timed step in µs
 */
export function timeStepsInterleaved (scenes, { warmup, steps, block, gc = null }) {
  for (const scene of scenes) {
    for (let i = 0; i < warmup; i++) scene.step()
  }
  const samples = scenes.map(() => new Float64Array(steps))
  for (let done = 0; done < steps; done += block) {
    const end = Math.min(steps, done + block)
    scenes.forEach((scene, s) => {
      if (gc) gc()
      timeSteps(scene, samples[s], done, end)
    })
  }
  return samples
}

function timeSteps (scene, out, from, to) {
  for (let i = from; i < to; i++) {
    const t0 = performance.now()
    scene.step()
    out[i] = (performance.now() - t0) * 1000
  }
}

/**
 * @param {Float64Array} samples
 * @returns {{ mean: number, p50: number, p99: number, max: number }}
 */
export function summarize (samples) {
  const sorted = Float64Array.from(samples).sort()
  let sum = 0
  for (let i = 0; i < sorted.length; i++) sum += sorted[i]
  return { mean: sum / sorted.length, p50: percentile(sorted, 0.5), p99: percentile(sorted, 0.99), max: sorted[sorted.length - 1] }
}

function percentile (sorted, q) {
  return sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))]
}

/**
 * Wall time of `run()` in ms.
 * @param {() => void} run
 */
export function timeMs (run) {
  const t0 = performance.now()
  run()
  return performance.now() - t0
}

/**
 * A function that forces a full garbage collection: globalThis.gc when Node
 * runs with --expose-gc, else one obtained by setting V8's flag at run time
 * (works on Node 20; null if it does not).
 * @returns {(() => void) | null}
 */
export function findGc () {
  if (typeof globalThis.gc === 'function') return globalThis.gc
  try {
    v8.setFlagsFromString('--expose-gc')
    const gc = vm.runInNewContext('gc')
    return typeof gc === 'function' ? gc : null
  } catch {
    return null
  }
}

/**
 * Heap use around `steps` calls of `step`: used heap after a forced GC
 * before, right after the run (no GC), and after a forced GC again, plus the
 * number of collections V8 ran by itself during the run. With no collection
 * during the run, (after run - before) / steps is the bytes allocated per
 * step; (after GC - before) / steps is what stays allocated.
 * @param {() => void} step @param {number} steps @param {() => void} gc
 */
export async function heapGrowth (step, steps, gc) {
  const collections = []
  const observer = new PerformanceObserver((list) => { for (const entry of list.getEntries()) collections.push(entry.startTime) })
  observer.observe({ entryTypes: ['gc'] })
  gc(); gc()
  const before = usedHeap()
  const start = performance.now()
  for (let i = 0; i < steps; i++) step()
  const end = performance.now()
  const afterRun = usedHeap()
  gc(); gc()
  const afterGc = usedHeap()
  await new Promise((resolve) => setTimeout(resolve, 50)) // gc entries are delivered asynchronously
  observer.disconnect()
  const collectionsDuringRun = collections.filter((t) => t >= start && t <= end).length
  return {
    steps,
    before,
    afterRun,
    afterGc,
    collectionsDuringRun,
    allocatedPerStep: collectionsDuringRun === 0 ? (afterRun - before) / steps : null,
    retainedPerStep: (afterGc - before) / steps
  }
}

function usedHeap () {
  return v8.getHeapStatistics().used_heap_size
}
