import { subtractBuckets, bucketQuantile, fractionAtMost, countAbove } from './prometheus-text.js'

/** The tick budget the issue sets: p99 of a 60 Hz tick under 8 ms. */
export const TICK_P99_GOAL_S = 0.008
/** A group commit slower than this (s; the commit histogram's last finite bound, server/metrics.js) is counted as a stall. */
export const SLOW_COMMIT_S = 0.05
/** One 60 Hz period: a tick that starts later than this has run into the next one. */
export const TICK_PERIOD_S = 1 / 60
/**
 * prom-client samples the event loop with a 10 ms timer
 * (monitorEventLoopDelay's resolution), and the histogram holds the whole
 * timer interval: an idle loop reads 10 ms. Delay = reading − resolution.
 */
export const EVENT_LOOP_RESOLUTION_S = 0.010
/** Seconds after every player has connected before the steady window opens. */
const SETTLE_S = 3

/**
 * @typedef {import('./metrics-sampler.js').Sample} Sample
 */

/**
 * The steady window: from SETTLE_S after the connection count first reached
 * its plateau (≥ 99% of the peak, or of `expectedClients` if reached) to the
 * last sample still at the plateau.
 * @param {Sample[]} samples @param {number} expectedClients
 * @returns {{ from: number, to: number, fromIndex: number, toIndex: number } | null}
 */
export function steadyWindow (samples, expectedClients) {
  const ok = samples.map((s, i) => ({ s, i })).filter(({ s }) => s.ok)
  if (ok.length < 2) return null
  const peak = Math.max(...ok.map(({ s }) => s.clients))
  if (peak <= 0) return null
  const plateau = 0.99 * Math.min(peak, expectedClients || peak)
  const first = ok.find(({ s }) => s.clients >= plateau)
  const last = [...ok].reverse().find(({ s }) => s.clients >= plateau)
  let start = ok.find(({ s }) => s.t >= first.s.t + SETTLE_S && s.t <= last.s.t) ?? first
  if (last.s.t - start.s.t < 1) start = first
  if (last.i <= start.i) return null
  return { from: start.s.t, to: last.s.t, fromIndex: start.i, toIndex: last.i }
}

/**
 * Figures of one run from the /metrics samples.
 * @param {Sample[]} samples
 * @param {{ expectedClients: number, baselineIndex?: number }} options baselineIndex: last sample before k6 started
 */
export function analyzeServerSamples (samples, { expectedClients, baselineIndex = 0 }) {
  const window = steadyWindow(samples, expectedClients)
  const baseline = samples.slice(0, baselineIndex + 1).filter((s) => s.ok).at(-1) ?? samples.find((s) => s.ok)
  if (!window) return { window: null, baseline, series: series(samples) }
  const a = samples[window.fromIndex]
  const b = samples[window.toIndex]
  const inWindow = samples.slice(window.fromIndex, window.toIndex + 1).filter((s) => s.ok)
  const seconds = b.t - a.t
  const ticks = subtractBuckets(b.tickBuckets, a.tickBuckets)
  const lag = subtractBuckets(b.lagBuckets, a.lagBuckets)
  const commits = subtractBuckets(b.commitBuckets, a.commitBuckets)
  const meanClients = mean(inWindow.map((s) => s.clients))
  const rss = median(inWindow.map((s) => s.rss))
  const heap = median(inWindow.map((s) => s.heapUsed))
  const rate = (field) => (b[field] - a[field]) / seconds
  const cpu = (field) => (b[field] !== null && a[field] !== null ? (b[field] - a[field]) / seconds : null)
  const machineBusy = a.machine && b.machine ? (b.machine.busyS - a.machine.busyS) / seconds : null
  return {
    window: { ...window, seconds },
    baseline,
    clients: { peak: Math.max(...samples.filter((s) => s.ok).map((s) => s.clients)), mean: meanClients },
    rooms: Math.max(...inWindow.map((s) => s.rooms)),
    ballsInFlight: mean(inWindow.map((s) => s.balls)),
    tick: {
      count: ticks.at(-1)?.count ?? 0,
      p50: bucketQuantile(ticks, 0.5),
      p99: bucketQuantile(ticks, 0.99),
      max: maxBucket(ticks),
      within8ms: fractionAtMost(ticks, TICK_P99_GOAL_S),
      perSecond: rate('ticks'),
      dropped: b.droppedTicks - a.droppedTicks
    },
    tickLag: { p50: bucketQuantile(lag, 0.5), p99: bucketQuantile(lag, 0.99), max: maxBucket(lag) },
    // over50ms: commits beyond the histogram's last finite bound, the stalls of the disk that hold every drop behind them.
    commit: { p50: bucketQuantile(commits, 0.5), p99: bucketQuantile(commits, 0.99), perSecond: (commits.at(-1)?.count ?? 0) / seconds, over50ms: countAbove(commits, SLOW_COMMIT_S) },
    eventLoop: {
      p99Median: eventLoopDelay(median(inWindow.map((s) => s.eventLoopP99))),
      p99Max: eventLoopDelay(Math.max(...inWindow.map((s) => s.eventLoopP99))),
      max: eventLoopDelay(Math.max(...inWindow.map((s) => s.eventLoopMax)))
    },
    memory: {
      rssBaseline: baseline?.rss ?? null,
      heapBaseline: baseline?.heapUsed ?? null,
      rss,
      heap,
      rssPerClient: baseline && meanClients > 0 ? (rss - baseline.rss) / meanClients : null,
      heapPerClient: baseline && meanClients > 0 ? (heap - baseline.heapUsed) / meanClients : null
    },
    traffic: {
      bytesOutPerSecond: rate('bytesOut'),
      messagesOutPerSecond: rate('messagesOut'),
      bytesPerClientPerSecond: meanClients > 0 ? rate('bytesOut') / meanClients : null,
      messagesPerClientPerSecond: meanClients > 0 ? rate('messagesOut') / meanClients : null,
      dropsPerSecond: rate('drops'),
      settlesPerSecond: rate('settles'),
      snapshotsSkipped: b.snapshotsSkipped - a.snapshotsSkipped,
      slowConsumersClosed: b.slowClosed - a.slowClosed
    },
    cpu: {
      server: cpu('serverCpuS'),
      k6: cpu('k6CpuS'),
      machine: machineBusy,
      /** Everything else running on the machine meanwhile (other tests, the driver itself). */
      others: machineBusy !== null ? Math.max(0, machineBusy - (cpu('serverCpuS') ?? 0) - (cpu('k6CpuS') ?? 0)) : null
    },
    k6Rss: median(inWindow.map((s) => s.k6Rss).filter((v) => v !== null)),
    serverErrors: errorsBetween(samples.find((s) => s.ok), samples.filter((s) => s.ok).at(-1)),
    series: series(samples)
  }
}

/** Errors the server counted between two samples, by code. */
function errorsBetween (a, b) {
  const out = {}
  for (const [code, count] of Object.entries(b?.errors ?? {})) {
    const delta = count - (a?.errors?.[code] ?? 0)
    if (delta > 0) out[code] = delta
  }
  return out
}

/**
 * Per-interval time series for the chart: each point covers the interval
 * since the previous sample.
 * @param {Sample[]} samples
 */
export function series (samples) {
  const points = []
  let previous = null
  for (const s of samples) {
    if (!s.ok) continue
    if (previous) {
      const dt = s.t - previous.t
      const ticks = subtractBuckets(s.tickBuckets, previous.tickBuckets)
      const lag = subtractBuckets(s.lagBuckets, previous.lagBuckets)
      points.push({
        t: s.t,
        clients: s.clients,
        balls: s.balls,
        tickP99Ms: ms(bucketQuantile(ticks, 0.99)),
        tickLagP99Ms: ms(bucketQuantile(lag, 0.99)),
        eventLoopP99Ms: ms(eventLoopDelay(s.eventLoopP99)),
        rssMb: s.rss / 2 ** 20,
        heapMb: s.heapUsed / 2 ** 20,
        serverCpu: s.serverCpuS !== null && previous.serverCpuS !== null ? 100 * (s.serverCpuS - previous.serverCpuS) / dt : null,
        k6Cpu: s.k6CpuS !== null && previous.k6CpuS !== null ? 100 * (s.k6CpuS - previous.k6CpuS) / dt : null,
        machineCpu: s.machine && previous.machine ? 100 * (s.machine.busyS - previous.machine.busyS) / dt : null,
        bytesOutPerClient: s.clients > 0 ? (s.bytesOut - previous.bytesOut) / dt / s.clients : null
      })
    }
    previous = s
  }
  return points
}

/** @param {number | null} reading seconds, as prom-client reports it */
function eventLoopDelay (reading) {
  return reading === null || reading === undefined ? null : Math.max(0, reading - EVENT_LOOP_RESOLUTION_S)
}

function ms (seconds) {
  return seconds === null || seconds === undefined ? null : seconds * 1000
}

function maxBucket (buckets) {
  let max = null
  let previous = 0
  for (const bucket of buckets) {
    if (bucket.count > previous) max = bucket.le
    previous = bucket.count
  }
  return max
}

function mean (values) {
  return values.length ? values.reduce((a, b) => a + b, 0) / values.length : null
}

function median (values) {
  if (!values.length) return null
  const sorted = [...values].sort((x, y) => x - y)
  const mid = sorted.length >> 1
  return sorted.length % 2 ? sorted[mid] : (sorted[mid - 1] + sorted[mid]) / 2
}
