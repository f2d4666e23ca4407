/**
 * A worker thread of the lean load generator: plays its share of the
 * players (lean-player.js over lean-socket.js), each on its own schedule,
 * then posts what they saw to the main thread (lean-generator.js) and ends.
 *
 * Each player: POST /api/session, GET /ws?token=… (upgrade), `join` on
 * `welcome`, one `drop` every dropIntervalMs from a random phase after
 * `joined`, until leaveAt; then it waits (at most drainMs) for its last
 * acknowledgements and settles and closes with 1000.
 *
 * At windowFrom and windowTo (epoch ms) the worker reads its own counters
 * and its thread's CPU time (/proc/thread-self/stat), so the main thread can
 * divide CPU by frames over the same steady window.
 */
import fs from 'node:fs'
import { parentPort, workerData } from 'node:worker_threads'
import { monitorEventLoopDelay } from 'node:perf_hooks'
import { LeanPlayer, PlayerStats, DropSightings } from './lean-player.js'
import { LeanSocket } from './lean-socket.js'

const JOIN_TIMEOUT_MS = 30_000
const DRAIN_POLL_MS = 200
const CLOCK_TICKS_PER_SECOND = 100 // USER_HZ on Linux
/** How often the event loop's lateness is sampled (ms): finer than a room tick (16.7 ms). */
const LOOP_DELAY_RESOLUTION_MS = 10

/** CPU seconds of the calling thread (user + system), or null where /proc has no thread-self. */
export function threadCpuSeconds () {
  try {
    const stat = fs.readFileSync('/proc/thread-self/stat', 'latin1')
    const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ')
    return (Number(fields[11]) + Number(fields[12])) / CLOCK_TICKS_PER_SECOND
  } catch {
    return null
  }
}

/**
 * Where a process's WebSocket is, from its base URL (http:// or ws://): host,
 * port and the path in front of /ws (a process behind the cluster's proxy
 * is under /n/{i}).
 * @param {string} baseUrl
 * @returns {{ host: string, port: number, prefix: string }}
 */
export function socketTarget (baseUrl) {
  const url = new URL(baseUrl)
  return { host: url.hostname.replace(/^\[|\]$/g, ''), port: Number(url.port || 80), prefix: url.pathname.replace(/\/+$/, '') }
}

/**
 * @typedef {object} WorkerPlan
 * @property {string} baseUrl http://127.0.0.1:PORT (checked loopback by the main thread)
 * @property {{ room: string, connectAt: number, leaveAt: number }[]} players epoch ms
 * @property {number} dropIntervalMs @property {number} bet @property {number} drainMs
 * @property {number} windowFrom @property {number} windowTo epoch ms
 * @property {'snapshots' | 'seeds'} [delivery] the players' `join.delivery` (default snapshots)
 */

/**
 * What the players of one worker share: the plan, where to connect, their
 * counters, and `finishOne` (called once per player when it is done).
 * @typedef {{ plan: WorkerPlan, entry: ReturnType<typeof socketTarget>, stats: PlayerStats, sightings: DropSightings, finishOne: () => void }} WorkerRun
 */

/** @param {WorkerPlan} plan @param {(result: object, transfer: ArrayBuffer[]) => void} done */
export function playWorkerPlan (plan, done) {
  const stats = new PlayerStats()
  const window = steadyWindow(plan, stats)
  let remaining = plan.players.length
  /** @type {WorkerRun} */
  const run = {
    plan,
    entry: socketTarget(plan.baseUrl),
    stats,
    sightings: new DropSightings(stats),
    finishOne () {
      if (--remaining > 0) return
      window.close()
      const { result, transfer } = workerResult(stats, window.figures)
      done(result, transfer)
    }
  }
  for (const spec of plan.players) {
    setTimeout(() => startPlayer(run, spec).catch((error) => {
      stats.error('X_GENERATOR', error.stack)
      run.finishOne()
    }), Math.max(0, spec.connectAt - Date.now()))
  }
}

/**
 * Sets the steady window on the players' clock (performance.now()) and
 * reads the worker's counters and CPU at its two ends, and how late its
 * event loop ran over it (`loopDelay`, ms: p50, p99, max). Every latency
 * the worker measures includes its own lag: a frame is timed when its
 * loop gets to it. `close` ends the window early when the players are done
 * first.
 * @param {WorkerPlan} plan @param {PlayerStats} stats
 */
function steadyWindow (plan, stats) {
  const figures = {}
  stats.steadyFrom = performance.now() + (plan.windowFrom - Date.now())
  stats.steadyTo = performance.now() + (plan.windowTo - Date.now())
  const read = () => ({ at: Date.now(), frames: stats.frames, textMessages: stats.textMessages, bytes: stats.bytes, cpuS: threadCpuSeconds() })
  const delay = monitorEventLoopDelay({ resolution: LOOP_DELAY_RESOLUTION_MS })
  const open = () => {
    figures.from = read()
    delay.enable()
  }
  const shut = () => {
    figures.to = read()
    if (!delay.disable()) return
    // Node records the whole interval between two of its timer's turns: the lateness is what exceeds the resolution.
    const ms = (ns) => Math.max(0, ns / 1e6 - LOOP_DELAY_RESOLUTION_MS)
    // A sample every resolution; none in a window shorter than that.
    figures.loopDelay = delay.count === 0 ? null : { p50Ms: ms(delay.percentile(50)), p99Ms: ms(delay.percentile(99)), maxMs: ms(delay.max) }
  }
  const timers = [
    setTimeout(open, Math.max(0, plan.windowFrom - Date.now())),
    setTimeout(shut, Math.max(0, plan.windowTo - Date.now()))
  ]
  return {
    figures,
    close () {
      if (!figures.to) shut()
      if (!figures.from) figures.from = figures.to
      for (const timer of timers) clearTimeout(timer)
    }
  }
}

/** What the worker posts to the main thread, and the sample buffers it transfers. @param {PlayerStats} stats */
function workerResult (stats, window) {
  const samples = {
    ackMs: stats.ackMs.toArray(),
    settledMs: stats.settledMs.toArray(),
    settleOverheadMs: stats.settleOverheadMs.toArray(),
    steadyAckMs: stats.steadyAckMs.toArray(),
    steadySettledMs: stats.steadySettledMs.toArray(),
    steadySightingMs: stats.steadySightingMs.toArray(),
    steadySightingTicks: stats.steadySightingTicks.toArray()
  }
  const result = {
    players: stats.players,
    joined: stats.joined,
    redirects: stats.redirects,
    dropsSent: stats.dropsSent,
    dropsAcked: stats.dropsAcked,
    dropsRefused: stats.dropsRefused,
    dropsSettled: stats.dropsSettled,
    unsettled: stats.unsettled,
    balanceMismatches: stats.balanceMismatches,
    frames: stats.frames,
    eventFrames: stats.eventFrames,
    eventsSeen: stats.eventsSeen,
    textMessages: stats.textMessages,
    bytes: stats.bytes,
    errors: Object.fromEntries(stats.errors),
    firstErrors: stats.firstErrors,
    window,
    samples
  }
  return { result, transfer: Object.values(samples).map((array) => array.buffer) }
}

/** Creates the player's session (POST /api/session), then plays it on a socket. @param {WorkerRun} run */
async function startPlayer (run, { room, leaveAt }) {
  const { plan, stats } = run
  let response
  try {
    response = await fetch(`${plan.baseUrl}/api/session`, { method: 'POST', signal: AbortSignal.timeout(30_000) })
  } catch (error) {
    stats.error('HTTP_ERROR', `POST /api/session: ${error.message}`)
    return run.finishOne()
  }
  const body = await response.text()
  if (response.status !== 201) {
    stats.error(`HTTP_${response.status}`, `POST /api/session: ${body.slice(0, 200)}`)
    return run.finishOne()
  }
  const { token } = JSON.parse(body)
  // It lives on in its socket's and timers' callbacks.
  new PlayedSocket(run, room, token, leaveAt)
}

/**
 * One player's socket, from open to close: it joins (again at the room's
 * process after E_WRONG_NODE), drops on a timer from a random phase, and at
 * leaveAt waits (at most drainMs) for its last answers before closing.
 */
class PlayedSocket {
  /** @param {WorkerRun} run @param {string} room @param {string} token @param {number} leaveAt epoch ms */
  constructor (run, room, token, leaveAt) {
    this.run = run
    this.token = token
    this.closedByUs = false
    this.dropTimer = null
    this.phaseTimer = null
    this.pollTimer = null
    /** @type {LeanSocket} */
    this.socket = null
    this.player = new LeanPlayer({ room, bet: run.plan.bet, stats: run.stats, delivery: run.plan.delivery, sightings: run.sightings, send: (text) => this.socket.sendText(text), redirect: (socketUrl) => this.moveTo(socketUrl) })
    this.open(run.entry)
    this.joinTimer = setTimeout(() => this.joinTimedOut(), JOIN_TIMEOUT_MS)
    this.leaveTimer = setTimeout(() => this.leave(), Math.max(0, leaveAt - Date.now()))
  }

  /** Opens the player's socket to the process at `target` (the entry URL, or the room's owner after E_WRONG_NODE). */
  open (target) {
    const current = new LeanSocket({ host: target.host, port: target.port, path: `${target.prefix}/ws?token=${encodeURIComponent(this.token)}` }, {
      onText: (text, at) => {
        this.player.receiveText(text, at)
        if (this.player.joined && this.dropTimer === null && this.phaseTimer === null && !this.player.leaving) this.startDropping()
      },
      onBinary: (buffer, start, end, at) => {
        this.player.receiveBinary(buffer, start, end, at)
      },
      onError: (error) => {
        if (this.closedByUs || current !== this.socket) return
        this.run.stats.error(error.status ? `HTTP_${error.status}` : 'WS_ERROR', error.message)
      },
      onClose: (code) => {
        // The socket left behind by a redirect closes quietly.
        if (current === this.socket) this.closed(code)
      }
    })
    this.socket = current
  }

  /** Leaves this socket (nothing was dropped on it) and joins again at the room's process. @param {string} socketUrl */
  moveTo (socketUrl) {
    const previous = this.socket
    this.open(socketTarget(socketUrl.replace(/\/ws$/, '')))
    previous.close(1000)
  }

  close () {
    this.closedByUs = true
    this.socket.close(1000)
  }

  joinTimedOut () {
    if (this.player.joined) return
    this.run.stats.error('X_JOIN_TIMEOUT', `no welcome/joined within ${JOIN_TIMEOUT_MS} ms`)
    this.close()
  }

  startDropping () {
    const interval = this.run.plan.dropIntervalMs
    if (interval <= 0) return
    // A random phase, so the players' drops do not arrive in waves.
    this.phaseTimer = setTimeout(() => {
      if (this.player.leaving) return
      this.player.drop()
      this.dropTimer = setInterval(() => this.player.drop(), interval)
    }, Math.random() * interval)
  }

  leave () {
    this.player.leave()
    clearTimeout(this.phaseTimer)
    clearInterval(this.dropTimer)
    const deadline = Date.now() + this.run.plan.drainMs
    this.pollTimer = setInterval(() => {
      if (this.player.drained || Date.now() >= deadline) {
        clearInterval(this.pollTimer)
        this.close()
      }
    }, DRAIN_POLL_MS)
  }

  closed (code) {
    clearTimeout(this.joinTimer)
    clearTimeout(this.leaveTimer)
    clearTimeout(this.phaseTimer)
    clearInterval(this.dropTimer)
    clearInterval(this.pollTimer)
    this.player.closed(code, this.closedByUs)
    this.run.finishOne()
  }
}

if (parentPort && workerData?.leanPlan) {
  playWorkerPlan(workerData.leanPlan, (result, transfer) => parentPort.postMessage(result, transfer))
}
