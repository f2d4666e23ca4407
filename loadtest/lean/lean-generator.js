/**
 * The lean load generator: PLAYERS simulated players (lean-player.js) in
 * WORKERS worker threads (lean-worker.js), spread over the first ROOMS
 * rooms the server lists, connecting over RAMP, dropping one ball every
 * DROP_INTERVAL for DURATION, then draining and leaving. For capacity runs,
 * where k6 (about 32 µs of CPU per frame received) runs out of CPU before
 * the server does; k6 stays the scenario and CI load test.
 *
 * It measures its own cost: CPU time of this whole process (every thread,
 * process.cpuUsage) and of each worker thread (/proc/thread-self/stat) over
 * the steady window (from SETTLE after the last player connected to the
 * first leave), divided by the frames received in it. Traffic goes to
 * loopback only, and every run is bounded: a worker that has not reported
 * by ramp + duration + drain + 60 s is stopped and the run fails.
 */
import { Worker } from 'node:worker_threads'
import { loopbackTarget } from '../driver/cli-args.js'

const WORKER_URL = new URL('./lean-worker.js', import.meta.url)
const START_DELAY_MS = 500
const DEADLINE_SLACK_MS = 60_000

/**
 * @typedef {object} LeanOptions
 * @property {string} baseUrl http://127.0.0.1:PORT or http://localhost:PORT
 * @property {number} players @property {number} rooms
 * @property {number} durationS steady phase (every player connected)
 * @property {number} [rampS] players connect spread over this (default 5 s)
 * @property {number} [dropIntervalMs] default 2000; 0 = no drops
 * @property {number} [bet] default 10
 * @property {number} [drainS] how long a leaving player waits for its last settles (default 15 s)
 * @property {number} [settleS] pause after the last connect before the window opens (default: 3 s, at most a quarter of the duration)
 * @property {number} [workers] worker threads (default 1)
 * @property {'snapshots' | 'seeds'} [delivery] the players' `join.delivery` (default snapshots)
 * @property {{ start?: () => void, end?: () => void }} [window] called when the steady window opens and closes (e.g. to read the server's CPU)
 */

/**
 * @param {number[] | Float64Array} values @param {number} q 0..1
 * @returns {number | null} nearest-rank quantile
 */
export function quantile (values, q) {
  if (values.length === 0) return null
  const sorted = Float64Array.from(values).sort()
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.ceil(q * sorted.length) - 1))]
}

/**
 * Runs the load and returns its figures; `passed` is false when any check failed.
 * @param {LeanOptions} options
 */
export async function runLeanLoad (options) {
  const baseUrl = loopbackTarget(options.baseUrl).replace(/\/$/, '')
  const players = options.players
  const rampMs = (options.rampS ?? 5) * 1000
  const durationMs = options.durationS * 1000
  const dropIntervalMs = options.dropIntervalMs ?? 2000
  const drainMs = (options.drainS ?? 15) * 1000
  const settleMs = (options.settleS ?? Math.min(3, options.durationS / 4)) * 1000
  const workerCount = Math.max(1, Math.min(options.workers ?? 1, players))

  const response = await fetch(`${baseUrl}/api/rooms`, { signal: AbortSignal.timeout(10_000) })
  if (!response.ok) throw new Error(`GET /api/rooms: ${response.status}`)
  const offered = (await response.json()).roomIds
  const rooms = offered.slice(0, Math.max(1, options.rooms))

  const startAt = Date.now() + START_DELAY_MS
  const leaveAt = startAt + rampMs + durationMs
  const windowFrom = startAt + rampMs + settleMs
  const windowTo = leaveAt
  const delivery = options.delivery ?? 'snapshots'
  const plans = Array.from({ length: workerCount }, () => ({ baseUrl, players: [], dropIntervalMs, bet: options.bet ?? 10, drainMs, windowFrom, windowTo, delivery }))
  for (let i = 0; i < players; i++) {
    plans[i % workerCount].players.push({ room: rooms[i % rooms.length], connectAt: startAt + (players > 1 ? i / players : 0) * rampMs, leaveAt })
  }

  const window = {}
  const read = () => ({ at: Date.now(), cpu: process.cpuUsage() })
  const timers = [
    setTimeout(() => { window.from = read(); options.window?.start?.() }, windowFrom - Date.now()),
    setTimeout(() => { window.to = read(); options.window?.end?.() }, windowTo - Date.now())
  ]
  const deadline = leaveAt + drainMs + DEADLINE_SLACK_MS
  let results
  try {
    results = await Promise.all(plans.map((plan) => runWorker(plan, deadline - Date.now())))
  } finally {
    for (const timer of timers) clearTimeout(timer)
  }
  if (!window.to) window.to = read()
  if (!window.from) window.from = window.to
  return summarize({ options, baseUrl, rooms, offered: offered.length, workerCount, results, window, dropIntervalMs })
}

/** Runs one worker to its report; a worker that does not report in time is terminated and reported as failed. */
function runWorker (plan, timeoutMs) {
  return new Promise((resolve) => {
    const worker = new Worker(WORKER_URL, { workerData: { leanPlan: plan } })
    let result = null
    const timer = setTimeout(() => {
      result ??= failedWorker(plan, 'X_GENERATOR_TIMEOUT', `worker did not finish within ${Math.round(timeoutMs / 1000)} s`)
      worker.terminate()
    }, timeoutMs)
    worker.once('message', (message) => {
      result ??= message
      worker.terminate()
    })
    worker.once('error', (error) => { result ??= failedWorker(plan, 'X_GENERATOR', error.stack) })
    worker.once('exit', () => {
      clearTimeout(timer)
      resolve(result ?? failedWorker(plan, 'X_GENERATOR', 'worker exited without reporting'))
    })
  })
}

function failedWorker (plan, code, detail) {
  return {
    players: plan.players.length, joined: 0, redirects: 0, dropsSent: 0, dropsAcked: 0, dropsRefused: 0, dropsSettled: 0, unsettled: 0, balanceMismatches: 0,
    frames: 0, eventFrames: 0, eventsSeen: 0, textMessages: 0, bytes: 0, errors: { [code]: 1 }, firstErrors: [`${code}: ${detail}`], window: {}, samples: { ackMs: [], settledMs: [], settleOverheadMs: [], steadyAckMs: [], steadySettledMs: [], steadySightingMs: [], steadySightingTicks: [] }
  }
}

/** The workers' results as one run: its counts, latencies, steady-window traffic and CPU, and whether it passed. */
function summarize ({ options, baseUrl, rooms, offered, workerCount, results, window, dropIntervalMs }) {
  const sum = (key) => results.reduce((total, result) => total + result[key], 0)
  const errors = mergeErrors(results)
  const samples = (key) => concatSamples(results, key)
  const delivery = options.delivery ?? 'snapshots'
  const traffic = steadyTraffic(results)
  const windowS = (window.to.at - window.from.at) / 1000
  const errorCount = Object.values(errors).reduce((total, count) => total + count, 0)
  const players = options.players
  const counts = { dropsSent: sum('dropsSent'), dropsAcked: sum('dropsAcked'), dropsSettled: sum('dropsSettled'), unsettled: sum('unsettled'), joined: sum('joined') }
  const failures = failuresOf({ ...counts, errorCount, players, dropIntervalMs, received: traffic.received, delivery, eventsSeen: sum('eventsSeen') })
  return {
    passed: failures.length === 0,
    failures,
    baseUrl,
    players,
    joined: counts.joined,
    /** Joins answered E_WRONG_NODE (clustered) and followed to the room's process. */
    redirects: sum('redirects'),
    rooms: rooms.length,
    roomsOffered: offered,
    workers: workerCount,
    delivery,
    dropIntervalMs,
    dropsSent: counts.dropsSent,
    dropsAcked: counts.dropsAcked,
    dropsRefused: sum('dropsRefused'),
    dropsSettled: counts.dropsSettled,
    unsettled: counts.unsettled,
    balanceMismatches: sum('balanceMismatches'),
    /** Seeds mode: drop-events frames received, and the other players' drops in them. */
    eventFrames: sum('eventFrames'),
    eventsSeen: sum('eventsSeen'),
    errors,
    errorCount,
    firstErrors: results.flatMap((result) => result.firstErrors).slice(0, 10),
    ackMs: latencies(samples('ackMs')),
    settledMs: latencies(samples('settledMs')),
    settleOverheadMs: percentiles(samples('settleOverheadMs')),
    /** The same, for the drops sent in the steady window only (no connects, no warm-up). */
    steady: {
      ackMs: latencies(samples('steadyAckMs')),
      settledMs: latencies(samples('steadySettledMs')),
      /** Seeds mode: another player's drop, sent → seen by the other sockets of its room (owner and watcher in the same worker). */
      sightingMs: latencies(samples('steadySightingMs')),
      /** The same sightings: room ticks from the ball's release to the frame that carried it (the room's batching and holds). */
      sightingTicks: percentiles(samples('steadySightingTicks'))
    },
    window: windowFigures(traffic, windowS, players),
    cpu: cpuFigures(window, windowS, traffic)
  }
}

/** Error counts by code, over every worker. */
function mergeErrors (results) {
  const errors = {}
  for (const result of results) for (const [code, count] of Object.entries(result.errors)) errors[code] = (errors[code] ?? 0) + count
  return errors
}

/** One sample kind of every worker, in one array. */
function concatSamples (results, key) {
  const arrays = results.map((result) => result.samples[key])
  const all = new Float64Array(arrays.reduce((total, array) => total + array.length, 0))
  let at = 0
  for (const array of arrays) { all.set(array, at); at += array.length }
  return all
}

const percentiles = (samples) => ({ p50: quantile(samples, 0.5), p99: quantile(samples, 0.99) })
const latencies = (samples) => ({ ...percentiles(samples), count: samples.length })

/** What the workers received in the steady window, as each counted it, and each worker's CPU per frame. */
function steadyTraffic (results) {
  let frames = 0
  let text = 0
  let bytes = 0
  const perWorker = []
  for (const { window: w } of results) {
    if (!w.from || !w.to) continue
    const workerFrames = w.to.frames - w.from.frames
    const workerText = w.to.textMessages - w.from.textMessages
    frames += workerFrames
    text += workerText
    bytes += w.to.bytes - w.from.bytes
    const cpuS = w.from.cpuS !== null && w.to.cpuS !== null ? w.to.cpuS - w.from.cpuS : null
    perWorker.push({ cpuS, received: workerFrames + workerText, usPerFrame: cpuS !== null && workerFrames + workerText > 0 ? cpuS * 1e6 / (workerFrames + workerText) : null, loopDelay: w.loopDelay ?? null })
  }
  return { frames, text, bytes, received: frames + text, perWorker }
}

/** Why the run failed (empty: it passed). */
function failuresOf ({ errorCount, joined, players, unsettled, dropsSent, dropsAcked, dropsSettled, dropIntervalMs, received, delivery, eventsSeen }) {
  const failures = []
  if (errorCount > 0) failures.push(`${errorCount} errors`)
  if (joined !== players) failures.push(`${joined} of ${players} players joined`)
  if (unsettled > 0) failures.push(`${unsettled} drops unsettled`)
  if (dropsAcked !== dropsSent) failures.push(`${dropsSent - dropsAcked} of ${dropsSent} drops not acknowledged`)
  if (dropsSettled !== dropsAcked) failures.push(`${dropsAcked - dropsSettled} of ${dropsAcked} acknowledged drops not settled`)
  if (dropIntervalMs > 0 && dropsSent === 0) failures.push('no drop was sent')
  if (received === 0) failures.push('no frame received in the steady window')
  if (delivery === 'seeds' && dropIntervalMs > 0 && players > 1 && eventsSeen === 0) failures.push('seeds mode: no other player\'s drop was seen')
  return failures
}

function windowFigures ({ frames, text, bytes, received }, windowS, players) {
  return {
    seconds: windowS,
    frames,
    textMessages: text,
    received,
    framesPerSecondPerPlayer: windowS > 0 ? received / windowS / players : null,
    bytesPerSecondPerPlayer: windowS > 0 ? bytes / windowS / players : null,
    receivedPerSecond: windowS > 0 ? received / windowS : null
  }
}

/** The generator's own CPU over the steady window (the main thread's process.cpuUsage covers every worker thread). */
function cpuFigures (window, windowS, { received, perWorker }) {
  const cpu = { user: window.to.cpu.user - window.from.cpu.user, system: window.to.cpu.system - window.from.cpu.system }
  const cpuS = (cpu.user + cpu.system) / 1e6
  return {
    seconds: cpuS,
    userS: cpu.user / 1e6,
    systemS: cpu.system / 1e6,
    shareOfCore: windowS > 0 ? cpuS / windowS : null,
    usPerFrame: received > 0 ? cpuS * 1e6 / received : null,
    userUsPerFrame: received > 0 ? cpu.user / received : null,
    perWorker,
    loopDelay: laggiest(perWorker)
  }
}

/**
 * The event-loop delay (ms: p50, p99, max) of the worker whose loop ran
 * latest at p99, or null without one: what the generator's own lag may
 * have added to the latencies it measured.
 * @param {{ loopDelay: { p50Ms: number, p99Ms: number, maxMs: number } | null }[]} perWorker
 */
export function laggiest (perWorker) {
  let worst = null
  for (const { loopDelay } of perWorker) if (loopDelay && (worst === null || loopDelay.p99Ms > worst.p99Ms)) worst = loopDelay
  return worst
}

const round = (value, digits = 1) => value === null || value === undefined ? '–' : Number(value).toFixed(digits)

/**
 * The figures in words, one per line.
 * @param {Awaited<ReturnType<typeof runLeanLoad>>} summary
 * @returns {string}
 */
export function formatLeanSummary (summary) {
  const s = summary
  const errors = Object.entries(s.errors).map(([code, count]) => `${code} ${count}`).join(', ') || 'none'
  const lines = [
    `lean generator (${s.delivery} delivery): ${s.players} players (${s.joined} joined${s.redirects ? `, ${s.redirects} after E_WRONG_NODE to the room's process` : ''}) in ${s.rooms} rooms${s.roomsOffered < s.rooms ? ` (server offers ${s.roomsOffered})` : ''}, ${s.workers} worker thread${s.workers === 1 ? '' : 's'}, one drop per ${s.dropIntervalMs} ms: ${s.passed ? 'PASS' : `FAIL (${s.failures.join('; ')})`}`,
    `  drops: ${s.dropsSent} sent, ${s.dropsAcked} acknowledged, ${s.dropsSettled} settled, ${s.dropsRefused} refused, ${s.unsettled} unsettled; balance mismatches ${s.balanceMismatches}; errors: ${errors}`,
    `  drop → dropped p50 / p99: ${round(s.ackMs.p50)} / ${round(s.ackMs.p99)} ms`,
    `  drop → settled p50 / p99: ${round(s.settledMs.p50, 0)} / ${round(s.settledMs.p99, 0)} ms (minus the fall: ${round(s.settleOverheadMs.p50)} / ${round(s.settleOverheadMs.p99)} ms)`,
    `  drops sent in the steady window (${s.steady.ackMs.count}): drop → dropped p50 / p99 ${round(s.steady.ackMs.p50)} / ${round(s.steady.ackMs.p99)} ms, drop → settled ${round(s.steady.settledMs.p50, 0)} / ${round(s.steady.settledMs.p99, 0)} ms`,
    ...(s.delivery === 'seeds' ? [`  seeds delivery: ${s.eventFrames} drop-events frames, ${s.eventsSeen} other players' drops seen; sent → seen by the room p50 / p99: ${round(s.steady.sightingMs.p50)} / ${round(s.steady.sightingMs.p99)} ms (${s.steady.sightingMs.count} sightings in the steady window), carried by a frame p50 / p99 ${round(s.steady.sightingTicks.p50, 0)} / ${round(s.steady.sightingTicks.p99, 0)} ticks after the ball's release`] : []),
    `  per player: ${round(s.window.framesPerSecondPerPlayer, 2)} frames/s, ${round(s.window.bytesPerSecondPerPlayer / 1000, 2)} KB/s payload (steady window ${round(s.window.seconds)} s, ${Math.round(s.window.receivedPerSecond ?? 0)} frames/s in all)`,
    `  generator CPU: ${round(s.cpu.usPerFrame, 2)} µs per frame received (user ${round(s.cpu.userUsPerFrame, 2)} µs), ${round((s.cpu.shareOfCore ?? 0) * 100)}% of a core; per worker thread: ${s.cpu.perWorker.map((w) => `${round(w.usPerFrame, 2)} µs`).join(', ') || '–'}`,
    `  generator event loop late by p50 / p99 / max ${round(s.cpu.loopDelay?.p50Ms)} / ${round(s.cpu.loopDelay?.p99Ms)} / ${round(s.cpu.loopDelay?.maxMs, 0)} ms (its worker thread lagging most; every latency above includes it)`
  ]
  for (const line of s.firstErrors) lines.push(`  error: ${line.split('\n')[0]}`)
  return lines.join('\n')
}
