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
import { LeanPlayer, PlayerStats, DropSightings } from './lean-player.js'
import { LeanSocket } from './lean-socket.js'

const JOIN_TIMEOUT_MS = 30_000
const DRAIN_POLL_MS = 200
const CLOCK_TICKS_PER_SECOND = 100 // USER_HZ on Linux

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

/** @param {WorkerPlan} plan @param {(result: object, transfer: ArrayBuffer[]) => void} done */
export function playWorkerPlan (plan, done) {
  const entry = socketTarget(plan.baseUrl)
  const stats = new PlayerStats()
  const sightings = new DropSightings(stats)
  const window = {}
  let remaining = plan.players.length

  // The steady window on the players' clock (performance.now()).
  stats.steadyFrom = performance.now() + (plan.windowFrom - Date.now())
  stats.steadyTo = performance.now() + (plan.windowTo - Date.now())
  const read = () => ({ at: Date.now(), frames: stats.frames, textMessages: stats.textMessages, bytes: stats.bytes, cpuS: threadCpuSeconds() })
  const windowTimers = [
    setTimeout(() => { window.from = read() }, Math.max(0, plan.windowFrom - Date.now())),
    setTimeout(() => { window.to = read() }, Math.max(0, plan.windowTo - Date.now()))
  ]

  const finishOne = () => {
    if (--remaining > 0) return
    if (!window.to) window.to = read()
    if (!window.from) window.from = window.to
    for (const timer of windowTimers) clearTimeout(timer)
    const samples = {
      ackMs: stats.ackMs.toArray(),
      settledMs: stats.settledMs.toArray(),
      settleOverheadMs: stats.settleOverheadMs.toArray(),
      steadyAckMs: stats.steadyAckMs.toArray(),
      steadySettledMs: stats.steadySettledMs.toArray(),
      steadySightingMs: stats.steadySightingMs.toArray()
    }
    done({
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
    }, Object.values(samples).map((array) => array.buffer))
  }

  for (const spec of plan.players) {
    setTimeout(() => connect(spec).catch((error) => {
      stats.error('X_GENERATOR', error.stack)
      finishOne()
    }), Math.max(0, spec.connectAt - Date.now()))
  }

  async function connect ({ room, leaveAt }) {
    let response
    try {
      response = await fetch(`${plan.baseUrl}/api/session`, { method: 'POST', signal: AbortSignal.timeout(30_000) })
    } catch (error) {
      stats.error('HTTP_ERROR', `POST /api/session: ${error.message}`)
      return finishOne()
    }
    const body = await response.text()
    if (response.status !== 201) {
      stats.error(`HTTP_${response.status}`, `POST /api/session: ${body.slice(0, 200)}`)
      return finishOne()
    }
    const { token } = JSON.parse(body)
    play(room, token, leaveAt)
  }

  function play (room, token, leaveAt) {
    let closedByUs = false
    let dropTimer = null
    let phaseTimer = null
    let pollTimer = null
    /** @type {LeanSocket} */
    let socket
    const player = new LeanPlayer({ room, bet: plan.bet, stats, delivery: plan.delivery, sightings, send: (text) => socket.sendText(text), redirect: (socketUrl) => moveTo(socketUrl) })

    /** Opens the player's socket to the process at `target` (the entry URL, or the room's owner after E_WRONG_NODE). */
    function open (target) {
      const current = new LeanSocket({ host: target.host, port: target.port, path: `${target.prefix}/ws?token=${encodeURIComponent(token)}` }, {
        onText (text, at) {
          player.receiveText(text, at)
          if (player.joined && dropTimer === null && phaseTimer === null && !player.leaving) startDropping()
        },
        onBinary (buffer, start, end, at) {
          player.receiveBinary(buffer, start, end, at)
        },
        onError (error) {
          if (closedByUs || current !== socket) return
          stats.error(error.status ? `HTTP_${error.status}` : 'WS_ERROR', error.message)
        },
        onClose (code) {
          // The socket left behind by a redirect closes quietly.
          if (current !== socket) return
          clearTimeout(joinTimer)
          clearTimeout(leaveTimer)
          clearTimeout(phaseTimer)
          clearInterval(dropTimer)
          clearInterval(pollTimer)
          player.closed(code, closedByUs)
          finishOne()
        }
      })
      socket = current
    }

    /** Leaves this socket (nothing was dropped on it) and joins again at the room's process. @param {string} socketUrl */
    function moveTo (socketUrl) {
      const previous = socket
      open(socketTarget(socketUrl.replace(/\/ws$/, '')))
      previous.close(1000)
    }

    open(entry)

    const close = () => {
      closedByUs = true
      socket.close(1000)
    }
    const joinTimer = setTimeout(() => {
      if (player.joined) return
      stats.error('X_JOIN_TIMEOUT', `no welcome/joined within ${JOIN_TIMEOUT_MS} ms`)
      close()
    }, JOIN_TIMEOUT_MS)
    const leaveTimer = setTimeout(leave, Math.max(0, leaveAt - Date.now()))

    function startDropping () {
      if (plan.dropIntervalMs <= 0) return
      // A random phase, so the players' drops do not arrive in waves.
      phaseTimer = setTimeout(() => {
        if (player.leaving) return
        player.drop()
        dropTimer = setInterval(() => player.drop(), plan.dropIntervalMs)
      }, Math.random() * plan.dropIntervalMs)
    }

    function leave () {
      player.leave()
      clearTimeout(phaseTimer)
      clearInterval(dropTimer)
      const deadline = Date.now() + plan.drainMs
      pollTimer = setInterval(() => {
        if (player.drained || Date.now() >= deadline) {
          clearInterval(pollTimer)
          close()
        }
      }, DRAIN_POLL_MS)
    }
  }
}

if (parentPort && workerData?.leanPlan) {
  playWorkerPlan(workerData.leanPlan, (result, transfer) => parentPort.postMessage(result, transfer))
}
