/**
 * Server CPU per frame, measured the same way for the bare WebSocket floor
 * and for our server (bench/ws-floor.js, loadtest/lean/capacity.js):
 *
 * - measureFloor: ws-floor-server.js (a `ws` server that only sends the
 *   same 190-byte binary frame to every socket every 50 ms, perMessageDeflate
 *   off, no game, no ledger) with N raw clients (lean-socket.js) in this
 *   process; its CPU (/proc/<pid>/stat) over the window / frames received.
 * - measureOurs: server/server.js (fresh SQLite ledger, per-address limits
 *   lifted) under the lean load generator (lean-generator.js), its CPU over
 *   the generator's steady window / frames the players received; with
 *   `sample`, its /metrics every second too (tick, lag, memory: the
 *   capacity criteria).
 *
 * With `pin`, the server runs on CPU 0 (`taskset -c 0`); the caller puts
 * itself on CPU 1 (pinSelf). The machine's other work over each window is
 * returned as `othersShare` (cores), so a disturbed run shows it.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { spawn, spawnSync } from 'node:child_process'
import { fileURLToPath } from 'node:url'
import { LeanSocket } from './lean-socket.js'
import { runLeanLoad } from './lean-generator.js'
import { startServer } from '../driver/server-process.js'
import { readProcStat, readMachineCpu, MetricsSampler } from '../driver/metrics-sampler.js'
import { readThreadSchedules, busiestThread } from '../driver/thread-schedule.js'
import { analyzeServerSamples } from '../driver/run-analysis.js'

const FLOOR_SERVER = fileURLToPath(new URL('./ws-floor-server.js', import.meta.url))
const CONNECT_BATCH = 100
const WARMUP_MS = 3000

/** taskset is there and this machine has at least two CPUs. */
export function canPin () {
  return os.availableParallelism() >= 2 && spawnSync('taskset', ['-p', String(process.pid)], { stdio: 'ignore' }).status === 0
}

/** Moves every thread of this process to `cpus`. @param {string} cpus */
export function pinSelf (cpus) {
  return spawnSync('taskset', ['-a', '-p', '-c', cpus, String(process.pid)], { stdio: 'ignore' }).status === 0
}

/** CPU seconds of everything on the machine but `pids` (busy time of all cores minus theirs), between two readings. */
function othersCpuS (machineFrom, machineTo, ownS) {
  if (!machineFrom || !machineTo) return null
  return Math.max(0, machineTo.busyS - machineFrom.busyS - ownS)
}

/**
 * Starts the bare floor server (pinned to `cpus` when given) and resolves
 * once it listens.
 * @param {{ cpus?: string, frameBytes?: number, intervalMs?: number }} options
 */
export async function startFloorServer ({ cpus, frameBytes = 190, intervalMs = 50 } = {}) {
  const args = [FLOOR_SERVER, '--frame-bytes', String(frameBytes), '--interval-ms', String(intervalMs)]
  const child = cpus ? spawn('taskset', ['-c', cpus, process.execPath, ...args], { stdio: ['ignore', 'pipe', 'inherit'] }) : spawn(process.execPath, args, { stdio: ['ignore', 'pipe', 'inherit'] })
  let output = ''
  const exited = new Promise((resolve) => child.once('exit', (code, signal) => resolve({ code, signal })))
  const port = await new Promise((resolve, reject) => {
    child.stdout.on('data', (chunk) => {
      output += chunk
      const match = /listening (\d+)/.exec(output)
      if (match) resolve(Number(match[1]))
    })
    exited.then(({ code, signal }) => reject(new Error(`floor server exited (${code ?? signal}) before listening`)))
  })
  return {
    pid: child.pid,
    port,
    /** SIGTERM; resolves with the frames it says it sent. */
    async stop () {
      child.kill('SIGTERM')
      const timer = setTimeout(() => child.kill('SIGKILL'), 10_000)
      await exited
      clearTimeout(timer)
      const match = /sent (\d+)/.exec(output)
      return match ? Number(match[1]) : null
    }
  }
}

/**
 * The floor: `clients` raw sockets on the bare server for `seconds` after a warm-up.
 * @param {{ clients: number, seconds: number, pin: boolean }} options
 * @returns {Promise<{ clients: number, connected: number, seconds: number, frames: number, framesPerSecond: number,
 *   serverCpuS: number, serverShare: number, serverUsPerFrame: number, serverKernelUsPerFrame: number,
 *   clientCpuS: number, clientUsPerFrame: number, clientKernelUsPerFrame: number, othersShare: number | null }>}
 *   …KernelUsPerFrame: the part of …UsPerFrame spent in the kernel (system time)
 */
export async function measureFloor ({ clients, seconds, pin }) {
  const server = await startFloorServer({ cpus: pin ? '0' : undefined })
  const sockets = []
  let frames = 0
  let connected = 0
  let errors = 0
  try {
    for (let i = 0; i < clients; i += CONNECT_BATCH) {
      for (let j = i; j < Math.min(clients, i + CONNECT_BATCH); j++) {
        sockets.push(new LeanSocket({ host: '127.0.0.1', port: server.port, path: '/' }, {
          onOpen: () => { connected++ },
          onText: () => { frames++ },
          onBinary: () => { frames++ },
          onClose: () => {},
          onError: () => { errors++ }
        }))
      }
      await new Promise((resolve) => setTimeout(resolve, 50))
    }
    await new Promise((resolve) => setTimeout(resolve, WARMUP_MS))
    const from = { at: performance.now(), frames, server: readProcStat(server.pid), client: process.cpuUsage(), machine: readMachineCpu() }
    await new Promise((resolve) => setTimeout(resolve, seconds * 1000))
    const to = { at: performance.now(), frames, server: readProcStat(server.pid), client: process.cpuUsage(from.client), machine: readMachineCpu() }
    const windowS = (to.at - from.at) / 1000
    const received = to.frames - from.frames
    const serverCpuS = to.server.cpuS - from.server.cpuS
    const clientCpuS = (to.client.user + to.client.system) / 1e6
    const others = othersCpuS(from.machine, to.machine, serverCpuS + clientCpuS)
    if (errors > 0 || connected < clients) throw new Error(`floor: ${connected} of ${clients} clients connected, ${errors} socket errors`)
    return {
      clients,
      connected,
      seconds: windowS,
      frames: received,
      framesPerSecond: received / windowS,
      serverCpuS,
      serverShare: serverCpuS / windowS,
      serverUsPerFrame: serverCpuS * 1e6 / received,
      serverKernelUsPerFrame: (to.server.kernelS - from.server.kernelS) * 1e6 / received,
      clientCpuS,
      clientUsPerFrame: clientCpuS * 1e6 / received,
      clientKernelUsPerFrame: to.client.system / received,
      othersShare: others === null ? null : others / windowS
    }
  } finally {
    for (const socket of sockets) socket.socket.destroy()
    await server.stop()
  }
}

/**
 * Our server under the lean generator's reference load (one drop per
 * player every 2 s, 20 Hz snapshots, `rooms` rooms), its players in
 * `delivery` mode.
 * @param {{ players: number, rooms?: number, durationS: number, rampS: number, pin: boolean, workers?: number,
 *   env?: Record<string, string>, profileDir?: string, sample?: boolean, delivery?: 'snapshots' | 'seeds' }} options
 *   sample: read /metrics every second and return the steady window's analysis (loadtest/driver/run-analysis.js)
 */
export async function measureOurs ({ players, rooms = 100, durationS, rampS, pin, workers = 1, env = {}, profileDir, sample = false, delivery = 'snapshots' }) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-floor-'))
  const server = await startServer({ dataDir: dir, logFile: path.join(dir, 'server.log'), cpus: pin ? '0' : undefined, env, profileDir })
  let from = null
  let to = null
  const read = () => ({ at: performance.now(), server: readProcStat(server.pid), machine: readMachineCpu(), threads: readThreadSchedules(server.pid) })
  const sampler = sample ? new MetricsSampler({ url: server.url, intervalMs: 1000, pids: { server: server.pid, k6: process.pid } }) : null
  let analysis = null
  try {
    if (sampler) {
      sampler.start()
      await new Promise((resolve) => setTimeout(resolve, 1500))
    }
    const baselineIndex = sampler ? sampler.samples.length - 1 : 0
    const summary = await runLeanLoad({
      baseUrl: server.url, players, rooms, durationS, rampS, dropIntervalMs: 2000, drainS: 15, workers, delivery,
      window: { start: () => { from = read() }, end: () => { to = read() } }
    })
    if (sampler) {
      await sampler.stop()
      analysis = analyzeServerSamples(sampler.samples, { expectedClients: players, baselineIndex })
    }
    const windowS = (to.at - from.at) / 1000
    const serverCpuS = to.server.cpuS - from.server.cpuS
    const others = othersCpuS(from.machine, to.machine, serverCpuS + summary.cpu.seconds)
    const writer = busiestThread(from.threads, to.threads, 'WorkerThread', windowS)
    return {
      summary,
      analysis,
      players,
      delivery,
      seconds: windowS,
      frames: summary.window.received,
      framesPerSecond: summary.window.received / windowS,
      serverCpuS,
      serverShare: serverCpuS / windowS,
      serverUsPerFrame: serverCpuS * 1e6 / summary.window.received,
      serverKernelUsPerFrame: (to.server.kernelS - from.server.kernelS) * 1e6 / summary.window.received,
      serverRss: to.server.rss,
      /** The SQLite writer thread's share of the window spent waiting for a CPU (null without /proc). */
      writerWaitShare: writer?.waitShare ?? null,
      othersShare: others === null ? null : others / windowS
    }
  } finally {
    if (sampler?.running) await sampler.stop()
    await server.stop()
    if (!profileDir) fs.rmSync(dir, { recursive: true, force: true })
  }
}

