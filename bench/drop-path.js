#!/usr/bin/env node
/**
 * The drop path's CPU, part by part: `node bench/drop-path.js [--drops N] [--rooms R] [--per-room P] [--delivery seeds|snapshots]`.
 *
 * A fixed workload through the real server code, in-process: R rooms of P
 * players (real Connection objects over stand-in sockets that count bytes),
 * each player dropping once every 2 s of room time (the reference load),
 * the arena's tick run by hand, and after each tick the group commit to the
 * real SQLite store (WAL, synchronous=FULL, its writer thread) awaited, so
 * every tick is one transaction whatever the machine's load. It stops after
 * N drops have been accepted and their balls have landed and been settled.
 *
 * Measured in CPU time, not wall-clock time (the machine is shared): the
 * process's clock (process.cpuUsage, exact) around each phase, and each
 * thread's own total over the window from /proc/self/task/TID/schedstat
 * (exact to the ns). Printed per drop:
 *   receive                a drop frame to a message: UTF-8, JSON, schema (timed alone on the same frames)
 *   accept                 the rest of Connection._receive: limits, nonce, HMAC drop seed, reserve
 *   ball release           Room.release: the engine turns the seed into the ball's initial state
 *   physics                the rooms' steps (landings and their settlements included)
 *   commit hand-over       the group commit's sync part: batch rows, posting them to the writer thread
 *   apply + owner replies  once durable: balances, `dropped`/`settled` JSON to the owner, feeds told
 *   room feeds             the tick after its steps: each room's seeds frames (or snapshots) encoded and
 *                          handed to sockets, the tally, idle rooms
 *   main thread, other     the rest of the main thread (microtasks, the writer's reply, GC, metrics)
 *   other threads          SQLite writer and checkpoint threads, GC helpers
 * and each tick's wait for its commit (wall clock: p50, p99, max).
 * Socket writes (ws framing and the kernel) are not in it: the sockets are
 * stand-ins; the lean load test's profile has them.
 */
import fs from 'node:fs'
import { withBenchLedger } from './temp-ledger.js'
import { Arena } from '../server/arena.js'
import { SINGLE_PROCESS } from '../server/coordination/modes.js'
import { createMetrics } from '../server/metrics.js'
import { openStore } from '../server/store/open-store.js'
import { createSession } from '../server/game/sessions.js'
import { Connection, createMessageParser } from '../server/realtime/connection.js'
import { TokenBucket } from '../server/limits/token-bucket.js'
import { ROOM_IDS } from '../protocol/room-id.js'
import { formatTable, fixed, int } from '../cli/text-table.js'
import { summarize } from './measure.js'

const USAGE = 'usage: node bench/drop-path.js [--drops N (6000)] [--rooms R (100)] [--per-room P (15)] [--delivery seeds|snapshots (seeds)] [--json]'
const DROP_EVERY_TICKS = 120
const WARMUP_TICKS = 600

const options = parseArgs(process.argv.slice(2))
const silentLog = { info () {}, warn () {}, error (...a) { console.error(...a) }, debug () {}, child () { return silentLog } }

/** A ws stand-in: what Connection touches, counting what it is sent. */
class StandInSocket {
  constructor () {
    this.bufferedAmount = 0
    this.bytes = 0
    this.frames = 0
  }

  on () {}
  send (data) {
    this.bytes += data.length
    this.frames++
    if (typeof data === 'string' && data.startsWith('{"type":"error"')) throw new Error(`the server refused: ${data}`)
  }
  ping () {}
  terminate () {}
  close () {}
  pause () {}
}

await withBenchLedger({ DROP_RATE: '1000', DROP_BURST: '1000', WS_HEARTBEAT_MS: '3600000' }, run)

async function run (config) {
  const store = await openStore(config.database)
  const metrics = createMetrics({ defaultMetrics: false })
  const { ownership, sequences, feed } = SINGLE_PROCESS.coordinate({ store, config, log: silentLog })
  const arena = new Arena({ config, store, ownership, sequences, feed, metrics, log: silentLog })
  await arena.start()
  const parseMessage = createMessageParser(config)
  const players = await seatPlayers(arena, store, config, metrics, parseMessage)
  const clock = instrument(arena)

  let accepted = 0
  let tick = 0
  /** @type {number[] | null} each tick's wait for its commit (wall ms), in the measured window */
  let commitMs = null
  const step = async () => {
    clock.receiveStarts()
    for (const player of players) {
      if (accepted >= options.drops || (tick + player.phase) % DROP_EVERY_TICKS !== 0) continue
      player.connection._receive(Buffer.from(`{"type":"drop","bet":1,"ref":${++player.refs}}`), false)
      accepted++
    }
    clock.tickStarts()
    arena.tick()
    clock.tickEnded()
    tick++
    const committing = performance.now()
    await arena.ledger.drain()
    if (commitMs !== null) commitMs.push(performance.now() - committing)
  }

  // Warm-up (WARMUP_TICKS, longer than a ball's flight): JIT, caches, the rooms' balls spread over their flight.
  const target = options.drops
  options.drops = Infinity
  while (tick < WARMUP_TICKS) await step()
  options.drops = target + accepted
  clock.reset()
  commitMs = []
  const before = await sample(metrics, players)
  // Steady state: as many balls land in the window as are dropped, about.
  while (accepted < options.drops) await step()
  const after = await sample(metrics, players)
  const spent = { ...clock.cpu }
  await arena.close()
  await store.close()
  report({ drops: target, ticks: tick, before, after, spent, parse: parseTime(parseMessage, target), commitMs })
}

/** Players with their sessions, connections and rooms, `options.perRoom` in each of `options.rooms`. */
async function seatPlayers (arena, store, config, metrics, parseMessage) {
  const players = []
  for (let r = 0; r < options.rooms; r++) {
    for (let p = 0; p < options.perRoom; p++) {
      const session = await createSession(store, config)
      const socket = new StandInSocket()
      const connection = new Connection({ socket, arena, parseMessage, metrics, log: silentLog, softLimit: 1 << 20, hardLimit: 1 << 22, messageLimiter: new TokenBucket({ rate: config.wsMessageRate, burst: config.wsMessageBurst }) })
      connection.authenticated(await arena.accounts.acquire(session.playerId))
      await arena.join(connection, ROOM_IDS[r % ROOM_IDS.length], options.delivery)
      players.push({ connection, socket, phase: players.length % DROP_EVERY_TICKS, refs: 0 })
    }
  }
  return players
}

/**
 * Each phase's CPU, charged by wrapping the real functions: a few clock
 * reads per tick and per commit, none per socket (a read is a system call).
 * process.cpuUsage, not threadCpuUsage: on Linux a thread's own clock
 * (RUSAGE_THREAD) only advances at scheduler ticks and context switches,
 * so short phases read 0 or a whole tick. The process clock is exact; it
 * includes other threads, which in this loop are idle but while a commit
 * runs: V8's helpers, and the writer's own tail after it answered, land in
 * whichever phase runs then (mostly the next tick's receive and accept),
 * a few µs per drop at 100 rooms, more with fewer drops per tick.
 */
function instrument (arena) {
  const cpu = { receive: 0, release: 0, physics: 0, handOver: 0, apply: 0, feeds: 0 }
  const now = () => { const u = process.cpuUsage(); return u.user + u.system }
  for (const room of arena.rooms.values()) {
    const release = room.release.bind(room)
    room.release = (drop) => { const t = now(); release(drop); cpu.release += now() - t }
  }
  const lifecycle = arena.drops
  const committed = lifecycle._committed.bind(lifecycle)
  lifecycle._committed = (...args) => { const t = now(); committed(...args); cpu.apply += now() - t }
  const ledger = arena.ledger
  const commit = ledger._commit.bind(ledger)
  // Its sync part (up to the store's promise); the continuation is `apply` (timed above) and the rest.
  ledger._commit = (batch) => { const t = now(); const done = commit(batch); cpu.handOver += now() - t; return done }
  // arena.tick: the rooms' steps, then ledger.flush() (only seals the batch: its commit runs after the
  // tick, timed above), then every room's delivery, the tally, idle rooms.
  const flush = ledger.flush.bind(ledger)
  let receiveStarted = 0
  let tickStarted = 0
  let flushed = 0
  ledger.flush = () => { flushed = now(); cpu.physics += flushed - tickStarted; flush() }
  return {
    cpu,
    receiveStarts () { receiveStarted = now() },
    tickStarts () { tickStarted = now(); cpu.receive += tickStarted - receiveStarted },
    tickEnded () { cpu.feeds += now() - flushed },
    reset () { for (const key in cpu) cpu[key] = 0 }
  }
}

/** Every clock and counter the report compares, at one moment. */
async function sample (metrics, players) {
  return {
    main: threadCpu(process.pid),
    mainSplit: process.threadCpuUsage(),
    // The window on the monotonic clock, µs (a V8 CPU profile's startTime is on it): to cut a --cpu-prof to it.
    at: Number(process.hrtime.bigint() / 1000n),
    threads: otherThreadsCpu(),
    process: process.cpuUsage(),
    settled: await counterValue(metrics.settles),
    bytes: sumOf(players, (p) => p.socket.bytes),
    frames: sumOf(players, (p) => p.socket.frames)
  }
}

function report ({ drops, ticks, before, after, spent, parse, commitMs }) {
  const commit = summarize(commitMs)
  const main = after.main - before.main
  const mainUser = (after.mainSplit.user - before.mainSplit.user) / drops
  const mainSystem = (after.mainSplit.system - before.mainSplit.system) / drops
  const threads = after.threads.micros - before.threads.micros
  const threadNames = [...after.threads.byName].map(([name, micros]) => [name, (micros - (before.threads.byName.get(name) ?? 0)) / drops])
  const processPerDrop = (after.process.user + after.process.system - before.process.user - before.process.system) / drops
  const settled = after.settled - before.settled
  const parts = [
    ['receive: frame to message (UTF-8, JSON, schema)', parse],
    ['accept (limits, nonce, HMAC seed, reserve; ws stand-in)', spent.receive - parse - spent.release],
    ['ball release (engine: seed to initial state)', spent.release],
    ['physics (room steps, landings)', spent.physics],
    ['commit hand-over (rows, post to writer thread)', spent.handOver],
    ['apply + owner replies (JSON) + feeds told', spent.apply],
    ['room feeds (encode, hand to sockets), rest of tick', spent.feeds]
  ]
  const named = parts.reduce((total, [, micros]) => total + micros, 0)
  parts.push(['main thread, other (microtasks, writer reply, GC)', main - named])
  parts.push(['other threads (SQLite writer, GC helpers)', threads])
  const total = main + threads
  if (options.json) {
    const perDrop = Object.fromEntries(parts.map(([name, micros]) => [name, micros / drops]))
    console.log(JSON.stringify({ drops, settled, ticks, window: [before.at, after.at], commitMs: commit, perDrop, totalPerDrop: total / drops, mainUserPerDrop: mainUser, mainSystemPerDrop: mainSystem, otherThreadsPerDrop: Object.fromEntries(threadNames), processPerDrop }))
    return
  }
  console.log(`\nDrop path: ${int(drops)} drops (${int(settled)} settled), ${options.rooms} rooms × ${options.perRoom} players, delivery ${options.delivery}, SQLite WAL + synchronous=FULL, one transaction per tick\n`)
  console.log(formatTable(
    [{ title: 'part', align: 'left' }, { title: 'CPU µs per drop' }, { title: 'share' }],
    [
      ...parts.map(([name, micros]) => [name, fixed(micros / drops, 1), `${fixed(100 * micros / total, 0)}%`]),
      ['in all (main thread + other threads)', fixed(total / drops, 1), '100%'],
      ['process.cpuUsage, same window', fixed(processPerDrop, 1), ''],
      ['main thread: user / kernel', `${fixed(mainUser, 1)} / ${fixed(mainSystem, 1)}`, '']
    ]
  ))
  console.log(`\nother threads by name, µs per drop: ${threadNames.map(([name, micros]) => `${name} ${fixed(micros, 1)}`).join(', ')}`)
  console.log(`each tick's wait for its commit (wall clock, ${int(commitMs.length)} ticks): p50 ${fixed(commit.p50, 2)} ms, p99 ${fixed(commit.p99, 2)} ms, max ${fixed(commit.max, 1)} ms`)
  console.log(`${fixed((after.frames - before.frames) / drops, 2)} frames and ${int((after.bytes - before.bytes) / drops)} bytes handed to sockets per drop; goal: ≤ 100 µs per drop in all`)
}

/** Main-thread CPU µs of parsing `drops` drop frames as Connection._receive does. */
function parseTime (parseMessage, drops) {
  const frames = Array.from({ length: drops }, (_, i) => Buffer.from(`{"type":"drop","bet":1,"ref":${i + 1}}`))
  const started = process.cpuUsage()
  for (const frame of frames) parseMessage(frame.toString('utf8'))
  const spent = process.cpuUsage(started)
  return spent.user + spent.system
}

/** CPU µs of one thread of this process, exact to the ns (/proc/self/task/TID/schedstat; Linux, else 0). */
function threadCpu (tid) {
  try {
    return Number(fs.readFileSync(`/proc/self/task/${tid}/schedstat`, 'utf8').split(' ')[0]) / 1000
  } catch {
    return 0
  }
}

/** CPU µs of every thread of this process but the main one, in all and by thread name. */
function otherThreadsCpu () {
  const byName = new Map()
  let dir
  try { dir = fs.readdirSync('/proc/self/task') } catch { return { micros: 0, byName } }
  let micros = 0
  for (const tid of dir) {
    if (Number(tid) === process.pid) continue
    const spent = threadCpu(tid)
    micros += spent
    let name = '?'
    try { name = fs.readFileSync(`/proc/self/task/${tid}/comm`, 'utf8').trim() } catch {}
    byName.set(name, (byName.get(name) ?? 0) + spent)
  }
  return { micros, byName }
}

async function counterValue (counter) {
  const { values } = await counter.get()
  return values.reduce((total, v) => total + v.value, 0)
}

function sumOf (items, value) {
  let total = 0
  for (const item of items) total += value(item)
  return total
}

function parseArgs (args) {
  const parsed = { drops: 6000, rooms: 100, perRoom: 15, delivery: 'seeds', json: false }
  for (let i = 0; i < args.length; i++) {
    const arg = args[i]
    if (arg === '--help' || arg === '-h') { console.log(USAGE); process.exit(0) }
    if (arg === '--json') { parsed.json = true; continue }
    const key = { '--drops': 'drops', '--rooms': 'rooms', '--per-room': 'perRoom', '--delivery': 'delivery' }[arg]
    const value = args[++i]
    if (!key || value === undefined) { console.error(`bad argument ${arg}\n${USAGE}`); process.exit(2) }
    parsed[key] = key === 'delivery' ? value : Number(value)
    if (key !== 'delivery' && !(Number.isSafeInteger(parsed[key]) && parsed[key] > 0)) { console.error(`${arg} needs a positive integer\n${USAGE}`); process.exit(2) }
  }
  if (!['seeds', 'snapshots'].includes(parsed.delivery)) { console.error(`--delivery must be seeds or snapshots\n${USAGE}`); process.exit(2) }
  return parsed
}
