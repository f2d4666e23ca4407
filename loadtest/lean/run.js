#!/usr/bin/env node
/**
 * `npm run loadtest:lean -- [options]`: the lean load generator against a
 * fresh server (server/server.js as a child process on 127.0.0.1, a fresh
 * SQLite ledger, per-address limits lifted) or against TARGET_URL
 * (loopback only). Prints the generator's figures and, for a server it
 * started, the server's CPU per frame sent over the same steady window.
 * Exit code 1 when a check failed, 2 for a bad command line.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { parseCommandLine } from '../../cli/command-line.js'
import { optionsOrExit } from '../../cli/usage-error.js'
import { parseDuration, positiveInteger, loopbackTarget, deliveryMode } from '../driver/cli-args.js'
import { startServer } from '../driver/server-process.js'
import { readProcStat, readThreadStat } from '../driver/metrics-sampler.js'
import { readThreadSchedules, busiestThread } from '../driver/thread-schedule.js'
import { summarizeCpuProfile, profileParts } from '../driver/cpu-profile-summary.js'
import { runLeanLoad, formatLeanSummary } from './lean-generator.js'
import { pinSelf } from './measure-server.js'

export const USAGE = `usage: npm run loadtest:lean -- [options]

  --players N            simulated players (default 100)
  --rooms N              rooms they are spread over (default 100)
  --duration TIME        steady phase (default 30s)
  --ramp TIME            players connect spread over this (default 10s)
  --drop-interval TIME   one drop per player this often (default 2s; 0 = never)
  --drain TIME           how long a leaving player waits for its last settles (default 15s)
  --bet N                credits per drop (default 10)
  --workers N            worker threads (default 1)
  --delivery MODE        the players' join.delivery: snapshots (default) or seeds
  --pin                  the server on CPU 0, the generator on CPU 1 (taskset)
  --profile              run the server under node --cpu-prof and print where its time went in the steady window
  -h, --help

TARGET_URL=http://127.0.0.1:PORT runs against a server already running there (loopback only).`

const OPTIONS = {
  help: { type: 'boolean', short: 'h' },
  players: { type: 'string' },
  rooms: { type: 'string' },
  duration: { type: 'string' },
  ramp: { type: 'string' },
  'drop-interval': { type: 'string' },
  drain: { type: 'string' },
  bet: { type: 'string' },
  workers: { type: 'string' },
  delivery: { type: 'string' },
  pin: { type: 'boolean', default: false },
  profile: { type: 'boolean', default: false }
}

/** @param {string[]} argv */
export function parseLeanArgs (argv) {
  const values = parseCommandLine(argv, OPTIONS, { repeated: 'last' })
  if (values.help) return { help: true }
  const optional = (name, parse, fallback) => values[name] === undefined ? fallback : parse(values[name], name)
  return {
    help: false,
    players: optional('players', positiveInteger, 100),
    rooms: optional('rooms', positiveInteger, 100),
    durationS: optional('duration', parseDuration, 30),
    rampS: optional('ramp', parseDuration, 10),
    dropIntervalMs: optional('drop-interval', parseDuration, 2) * 1000,
    drainS: optional('drain', parseDuration, 15),
    bet: optional('bet', positiveInteger, 10),
    workers: optional('workers', positiveInteger, 1),
    delivery: optional('delivery', deliveryMode, 'snapshots'),
    pin: values.pin,
    profile: values.profile
  }
}

async function main () {
  const options = optionsOrExit(parseLeanArgs, process.argv.slice(2), USAGE)
  const target = process.env.TARGET_URL ? loopbackTarget(process.env.TARGET_URL) : null
  let server = null
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-lean-'))
  if (!target) {
    server = await startServer({ dataDir: dir, logFile: path.join(dir, 'server.log'), cpus: options.pin ? '0' : undefined, profileDir: options.profile ? path.join(dir, 'profile') : undefined })
    console.log(`server: pid ${server.pid} at ${server.url}${options.pin ? ', pinned to CPU 0' : ''} (log: ${path.join(dir, 'server.log')})`)
  }
  if (options.pin && !pinSelf('1')) console.log('taskset not available: the generator is not pinned')
  const readServer = () => server ? { at: performance.now(), ns: process.hrtime.bigint(), stat: readProcStat(server.pid), main: readThreadStat(server.pid, server.pid), threads: readThreadSchedules(server.pid) } : null
  let serverFrom = null
  let serverTo = null
  let summary
  try {
    summary = await runLeanLoad({
      ...options,
      baseUrl: target ?? server.url,
      window: { start: () => { serverFrom = readServer() }, end: () => { serverTo = readServer() } }
    })
  } finally {
    if (server) await server.stop()
  }
  console.log(formatLeanSummary(summary))
  if (serverFrom?.stat && serverTo?.stat) {
    const seconds = (serverTo.at - serverFrom.at) / 1000
    const cpuS = serverTo.stat.cpuS - serverFrom.stat.cpuS
    const mainS = serverFrom.main && serverTo.main ? serverTo.main.cpuS - serverFrom.main.cpuS : null
    const drops = summary.steady.ackMs.count
    console.log(`  server CPU: ${(cpuS / seconds * 100).toFixed(1)}% of a core${mainS === null ? '' : ` (main thread ${(mainS / seconds * 100).toFixed(1)}%)`}, ${(cpuS * 1e6 / summary.window.received).toFixed(2)} µs per frame its players received, ${(cpuS * 1e6 / seconds / summary.players).toFixed(0)} µs per player-second, ${drops > 0 ? (cpuS * 1e6 / drops).toFixed(0) : '–'} µs per drop sent in the window`)
    const writer = busiestThread(serverFrom.threads, serverTo.threads, 'WorkerThread', seconds)
    if (writer) console.log(`  SQLite writer thread: on a CPU ${(writer.runShare * 100).toFixed(1)}% of the window, runnable but waiting for one ${(writer.waitShare * 100).toFixed(1)}%`)
  }
  if (options.profile && server && serverFrom && serverTo) printProfile(path.join(dir, 'profile'), serverFrom, serverTo, summary.steady.ackMs.count)
  process.exitCode = summary.passed ? 0 : 1
}

/**
 * The parts of a drop's cost on the server's main thread, for the profile's
 * per-drop table: each sample goes to the deepest frame's part
 * (cpu-profile-summary.js profileParts). Files are repository paths.
 */
export const DROP_COST_PARTS = [
  { name: 'HMAC drop seed', match: (f) => f.functionName === 'deriveDropSeed' },
  { name: 'owner replies (dropped, settled: JSON)', match: (f) => f.functionName === '_sendToOwnerConnections' },
  { name: 'room feeds (events and snapshots: encode, queue)', match: (f) => /^server\/realtime\/delivery-/.test(f.file) || (f.file === 'server/rooms/room.js' && f.functionName === 'deliver') || /^protocol\/(snapshot|drop-events)-codec/.test(f.file) },
  { name: 'socket writes (every frame, at the end of the turn)', match: (f) => f.file === 'server/realtime/write-batcher.js' || f.file.endsWith('/ws/lib/sender.js') },
  { name: 'physics (room steps)', match: (f) => f.file.startsWith('engine/') || (f.file === 'server/rooms/room.js' && f.functionName === 'step') },
  { name: 'ledger commit (group commit, hand-over to the store, apply)', match: (f) => /^server\/(store\/|game\/money)/.test(f.file) || (f.file === 'server/game/drop.js' && f.functionName !== 'createDrop') || f.functionName === '_committed' },
  { name: 'receiving and validation (ws parser, JSON, schema, checks)', match: (f) => f.file.endsWith('/ws/lib/receiver.js') || f.file === 'server/realtime/connection.js' || f.functionName === 'accept' || f.file.includes('/ajv/') },
  { name: 'metrics (prom-client)', match: (f) => f.file.includes('/prom-client/') },
  { name: 'garbage collection', match: (f) => f.functionName === '(garbage collector)' }
]

/** Where the server's time went between two readings (V8 profiles use process.hrtime's monotonic clock, in µs). */
function printProfile (dir, from, to, drops) {
  const file = fs.existsSync(dir) ? fs.readdirSync(dir).find((name) => name.endsWith('.cpuprofile')) : null
  if (!file) return console.log(`no .cpuprofile in ${dir}`)
  const profile = JSON.parse(fs.readFileSync(path.join(dir, file), 'utf8'))
  const window = { from: Number(from.ns / 1000n) - profile.startTime, to: Number(to.ns / 1000n) - profile.startTime }
  const summary = summarizeCpuProfile(profile, { top: 20, ...window })
  if (drops > 0 && from.main && to.main) {
    // The profile's shares of the main thread's busy time, scaled to its CPU time (a loaded machine stretches wall time).
    const mainUs = (to.main.cpuS - from.main.cpuS) * 1e6
    const otherThreadsUs = (to.stat.cpuS - from.stat.cpuS) * 1e6 - mainUs
    const { parts } = profileParts(profile, DROP_COST_PARTS, window)
    console.log(`\nserver CPU per drop (${drops} drops in the steady window; every frame they cause included):`)
    for (const part of parts) console.log(`  ${(part.share * mainUs / drops).toFixed(1).padStart(7)} µs  ${part.name}`)
    console.log(`  ${(otherThreadsUs / drops).toFixed(1).padStart(7)} µs  other threads (the SQLite writer's transactions, GC helpers, and under --profile the profiler's sampling thread)`)
    console.log(`  ${((mainUs + otherThreadsUs) / drops).toFixed(1).padStart(7)} µs  in all`)
  }
  const pct = (share) => `${(share * 100).toFixed(1)}%`.padStart(6)
  console.log(`\nserver profile (${path.join(dir, file)}), steady window, ${summary.totalMs.toFixed(0)} ms sampled; share of wall time by area:`)
  for (const area of summary.areas.slice(0, 12)) console.log(`  ${pct(area.share)}  ${area.area}`)
  console.log('self time, top functions:')
  for (const entry of summary.selfTop) console.log(`  ${pct(entry.share)}  ${entry.name}`)
  console.log('inclusive time, our functions:')
  for (const entry of summary.inclusiveTop.slice(0, 15)) console.log(`  ${pct(entry.share)}  ${entry.name}`)
}

if (process.argv[1] && path.resolve(process.argv[1]) === new URL(import.meta.url).pathname) await main()
