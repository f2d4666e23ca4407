import fs from 'node:fs'
import { parsePrometheusText, scalar, byLabel, histogramBuckets } from './prometheus-text.js'

const CLOCK_TICKS_PER_SECOND = 100 // USER_HZ on Linux

/**
 * @typedef {object} Sample one reading of the server's /metrics (cumulative counters as read)
 * @property {number} t seconds since the sampler started
 * @property {boolean} ok /metrics answered
 * @property {number} scrapeMs how long /metrics took to answer
 * @property {number} clients @property {number} rooms @property {number} balls
 * @property {number} rss @property {number} heapUsed bytes
 * @property {number} eventLoopP99 @property {number} eventLoopMax seconds, since the previous scrape
 * @property {number} tickLagCurrent seconds
 * @property {{ le: number, count: number }[]} tickBuckets cumulative tick-duration histogram
 * @property {{ le: number, count: number }[]} lagBuckets cumulative tick-lag histogram
 * @property {{ le: number, count: number }[]} commitBuckets cumulative group-commit histogram
 * @property {number} ticks @property {number} droppedTicks @property {number} drops @property {number} settles
 * @property {number} bytesOut @property {number} messagesOut @property {number} snapshotsSkipped @property {number} slowClosed
 * @property {Record<string, number>} errors by code
 * @property {number | null} serverCpuS CPU seconds of the server process (from /proc, else from /metrics)
 * @property {number | null} k6CpuS CPU seconds of k6 (from /proc)
 * @property {number | null} k6Rss bytes
 * @property {{ busyS: number, totalS: number } | null} machine CPU seconds of every core (busy: not idle or iowait)
 */

/**
 * Reads GET /metrics (and /proc for CPU) every `intervalMs` until stopped.
 * Scrapes never overlap: a slow answer delays the next one.
 */
export class MetricsSampler {
  /**
   * @param {{ url: string, intervalMs: number, pids?: { server?: number, k6?: number } }} options
   */
  constructor ({ url, intervalMs, pids = {} }) {
    this.url = url
    this.intervalMs = intervalMs
    this.pids = pids
    /** @type {Sample[]} */
    this.samples = []
    this.running = false
    this.startedAt = 0
    this.timer = null
    this.loop = null
  }

  start () {
    this.running = true
    this.startedAt = performance.now()
    this.loop = this._run()
  }

  /** Seconds since start. */
  now () {
    return (performance.now() - this.startedAt) / 1000
  }

  async stop () {
    this.running = false
    if (this.wake) this.wake()
    await this.loop
  }

  async _run () {
    while (this.running) {
      const due = performance.now() + this.intervalMs
      this.samples.push(await this.sampleOnce())
      const wait = due - performance.now()
      if (wait > 0 && this.running) await new Promise((resolve) => { this.wake = resolve; this.timer = setTimeout(resolve, wait) })
      clearTimeout(this.timer)
    }
  }

  /** @returns {Promise<Sample>} */
  async sampleOnce () {
    const t = this.now()
    const started = performance.now()
    let samples = null
    try {
      const response = await fetch(`${this.url}/metrics`, { signal: AbortSignal.timeout(5000) })
      if (response.ok) samples = parsePrometheusText(await response.text())
    } catch {}
    const scrapeMs = performance.now() - started
    const proc = (pid) => (pid ? readProcStat(pid) : null)
    const server = proc(this.pids.server)
    const k6 = proc(this.pids.k6)
    const machine = readMachineCpu()
    if (!samples) return { t, ok: false, scrapeMs, serverCpuS: server?.cpuS ?? null, k6CpuS: k6?.cpuS ?? null, k6Rss: k6?.rss ?? null, machine }
    const get = (name) => scalar(samples, name) ?? 0
    return {
      t,
      ok: true,
      scrapeMs,
      clients: get('plinko_ws_clients'),
      rooms: get('plinko_rooms'),
      balls: get('plinko_balls_in_flight'),
      rss: server?.rss ?? get('plinko_process_resident_memory_bytes'),
      heapUsed: get('plinko_nodejs_heap_size_used_bytes'),
      eventLoopP99: get('plinko_nodejs_eventloop_lag_p99_seconds'),
      eventLoopMax: get('plinko_nodejs_eventloop_lag_max_seconds'),
      tickLagCurrent: get('plinko_tick_lag_current_seconds'),
      tickBuckets: histogramBuckets(samples, 'plinko_tick_duration_seconds'),
      lagBuckets: histogramBuckets(samples, 'plinko_tick_lag_seconds'),
      commitBuckets: histogramBuckets(samples, 'plinko_ledger_commit_seconds'),
      ticks: get('plinko_ticks_total'),
      droppedTicks: get('plinko_ticks_dropped_total'),
      drops: get('plinko_drops_total'),
      settles: get('plinko_settles_total'),
      bytesOut: get('plinko_ws_bytes_out_total'),
      messagesOut: get('plinko_ws_messages_out_total'),
      snapshotsSkipped: get('plinko_snapshots_skipped_total'),
      slowClosed: get('plinko_ws_slow_consumers_closed_total'),
      errors: byLabel(samples, 'plinko_errors_total', 'code'),
      serverCpuS: server?.cpuS ?? get('plinko_process_cpu_seconds_total'),
      k6CpuS: k6?.cpuS ?? null,
      k6Rss: k6?.rss ?? null,
      machine
    }
  }
}

/**
 * CPU seconds (user + system, and the system part alone: time in the
 * kernel), resident memory and nice value of a process, or null when it
 * is gone or /proc is not there.
 * @param {number} pid
 */
export function readProcStat (pid) {
  return readStat(`/proc/${pid}/stat`)
}

/** The same for one thread of a process (its main thread: tid = pid). @param {number} pid @param {number} tid */
export function readThreadStat (pid, tid) {
  return readStat(`/proc/${pid}/task/${tid}/stat`)
}

function readStat (file) {
  try {
    const stat = fs.readFileSync(file, 'utf8')
    // Fields after the command name (which may contain spaces) start at ") ".
    const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ')
    const utime = Number(fields[11])
    const stime = Number(fields[12])
    const rssPages = Number(fields[21])
    return { cpuS: (utime + stime) / CLOCK_TICKS_PER_SECOND, kernelS: stime / CLOCK_TICKS_PER_SECOND, rss: rssPages * 4096, nice: Number(fields[16]) }
  } catch {
    return null
  }
}

/**
 * CPU seconds of the whole machine since boot (all cores), from /proc/stat:
 * busy = everything but idle and iowait. Null without /proc.
 */
export function readMachineCpu () {
  try {
    const fields = fs.readFileSync('/proc/stat', 'utf8').split('\n', 1)[0].trim().split(/\s+/).slice(1, 9).map(Number)
    const total = fields.reduce((a, b) => a + b, 0)
    const idle = fields[3] + fields[4]
    return { busyS: (total - idle) / CLOCK_TICKS_PER_SECOND, totalS: total / CLOCK_TICKS_PER_SECOND }
  } catch {
    return null
  }
}
