#!/usr/bin/env node
/**
 * Server tick benchmark: `node bench/server-ticks.js [--quick]`.
 *
 * The arena's 60 Hz loop, on one core (the script re-runs itself under
 * `taskset -c 0` when taskset exists), with 1,000 rooms on the 16-row board,
 * each with one connected client and 10 balls in flight: when a ball
 * settles its owner drops another, through the full server path (rate
 * limiter, nonce, HMAC drop seed, group commit to SQLite in WAL mode with
 * synchronous=FULL, `dropped`/`settled` events, 20 Hz binary room frames to
 * the client). Clients are in-process stand-ins that count bytes, so the figure
 * is the loop's own work, not the kernel's.
 *
 * Prints p50/p99/max of the tick (every room stepped, landings collected,
 * snapshots encoded and handed to the client), of the group-commit
 * transaction that follows each tick (on the SQLite store's writer thread:
 * from hand-over until durable), of the tick lag, and of the engine alone
 * stepping the same load.
 * Goal: tick p99 < 8 ms. Exit code 0 whatever the figures.
 */
import { spawnSync } from 'node:child_process'
import { fileURLToPath } from 'node:url'
import { DropSimulator } from '../engine/index.js'
import { Arena } from '../server/arena.js'
import { SINGLE_PROCESS } from '../server/coordination/modes.js'
import { withBenchLedger } from './temp-ledger.js'
import { createMetrics } from '../server/metrics.js'
import { openStore } from '../server/store/open-store.js'
import { createSession } from '../server/game/sessions.js'
import { Room } from '../server/rooms/room.js'
import { snapshotsDelivery } from '../server/realtime/delivery-snapshots.js'
import { NO_ADDRESS_LIMITS } from '../server/realtime/ip-limits.js'
import { boardOf } from '../server/rooms/boards.js'
import { deriveDropSeed } from '../server/fairness/seeds.js'
import { summarize } from './measure.js'
import { formatTable, fixed, int, bytes } from '../cli/text-table.js'

const ROOMS = 1000
const BALLS_PER_ROOM = 10
const GOAL_P99_MS = 8
const USAGE = 'usage: node bench/server-ticks.js [--quick]'

const args = process.argv.slice(2)
for (const arg of args) {
  if (arg === '--help' || arg === '-h') { console.log(USAGE); process.exit(0) }
  if (arg !== '--quick') { console.error(`unknown argument ${arg}\n${USAGE}`); process.exit(2) }
}
const quick = args.includes('--quick')
pinToOneCore()

const WARMUP_SECONDS = quick ? 4 : 8
const MEASURE_SECONDS = quick ? 4 : 20

/** An in-process client: counts what the arena sends and re-drops when its ball settles. */
class BenchClient {
  constructor (arena, account, room) {
    this.arena = arena
    this.account = account
    this.room = room
    // In-process players have no address to share buckets with.
    this.ipLimits = NO_ADDRESS_LIMITS
    this.drops = 0
    this.eventBytes = 0
    this.snapshotBytes = 0
    this.errors = 0
  }

  sendEvent (text, type) {
    this.eventBytes += text.length
    if (type === 'settled' && this.arena.accepting) this.drop()
  }

  sendRoomFrame (frame) { this.snapshotBytes += frame.payload.length; return true }
  sendEventFrame (frame) { this.snapshotBytes += frame.payload.length; return true }
  sendError () { this.errors++ }
  drop () {
    this.arena.drop(this, { bet: 1 })
    this.drops++
  }
}

const silentLog = { info () {}, warn () {}, error (...a) { console.error(...a) }, debug () {} }
await withBenchLedger({ DROP_RATE: '1000', DROP_BURST: '1000' }, run)

/** @param {import('../server/config.js').Config} config */
async function run (config) {
  /** What is timed while `measuring`: each group commit, tick and tick lag (ms). */
  const probe = { measuring: false, commits: [], ticks: [], lags: [] }
  const store = await openStore(config.database)
  timeCommits(store, probe)
  const { ownership, sequences, feed } = SINGLE_PROCESS.coordinate({ store, config, log: silentLog })
  const arena = new Arena({ config, store, ownership, sequences, feed, metrics: createMetrics({ defaultMetrics: false }), log: silentLog })
  await arena.start()

  const board = boardOf('16-medium')
  const clients = await seatClients(arena, store, config, board)
  timeTicks(arena.scheduler, probe)
  await warmUp(arena, clients)
  const measured = await measure(arena, clients, probe)

  arena.stopAccepting()
  arena.scheduler.stop()
  await arena.ledger.drain()
  await store.close()
  printFigures(board, probe, measured)
}

/** Times each group commit from handing the batch over until it is durable (on the store's writer thread, off the event loop). */
function timeCommits (store, probe) {
  const commitBatch = store.commitBatch.bind(store)
  store.commitBatch = async (batch) => {
    const started = process.hrtime.bigint()
    const outcome = await commitBatch(batch)
    if (probe.measuring) probe.commits.push(Number(process.hrtime.bigint() - started) / 1e6)
    return outcome
  }
}

/** One player in each of ROOMS rooms of `board`, each with its own session and snapshot feed. */
async function seatClients (arena, store, config, board) {
  const clients = []
  for (let i = 0; i < ROOMS; i++) {
    const session = await createSession(store, config)
    const account = await arena.accounts.acquire(session.playerId)
    const room = new Room({ id: `bench-${i}`, board, snapshotEvery: 60 / config.snapshotHz, snapshotPhase: i })
    arena.rooms.adopt(room)
    const client = new BenchClient(arena, account, room)
    account.connections.add(client)
    client.feed = room.join(client, snapshotsDelivery)
    clients.push(client)
  }
  return clients
}

/** Times each tick and its lag; everything else is the production loop. */
function timeTicks (scheduler, probe) {
  const tick = scheduler.onTick
  scheduler.onTick = () => {
    const started = process.hrtime.bigint()
    tick()
    if (probe.measuring) probe.ticks.push(Number(process.hrtime.bigint() - started) / 1e6)
  }
  const runTick = scheduler._runTick.bind(scheduler)
  scheduler._runTick = (lagNs) => {
    if (probe.measuring) probe.lags.push(Number(lagNs) / 1e6)
    runTick(lagNs)
  }
}

/** Starts the clock and fills the rooms gradually (one ball per room every 25 ticks) so landings spread out. */
async function warmUp (arena, clients) {
  let filled = 0
  const fill = () => {
    if (filled++ < BALLS_PER_ROOM) for (const client of clients) client.drop()
  }
  fill()
  const filler = setInterval(fill, 25 * 1000 / 60)
  arena.run()
  await sleep(WARMUP_SECONDS * 1000)
  clearInterval(filler)
}

/** The counters before and after MEASURE_SECONDS of steady play, and the mean balls in flight. */
async function measure (arena, clients, probe) {
  const scheduler = arena.scheduler
  const counters = () => ({ ticks: scheduler.ticks, dropped: scheduler.droppedTicks, drops: sum(clients, 'drops'), snapshotBytes: sum(clients, 'snapshotBytes'), eventBytes: sum(clients, 'eventBytes') })
  const before = counters()
  let ballSamples = 0
  let ballTotal = 0
  const ballSampler = setInterval(() => {
    for (const room of arena.rooms.values()) ballTotal += room.ballsInFlight
    ballSamples++
  }, 250)
  const startedAt = performance.now()
  probe.measuring = true
  await sleep(MEASURE_SECONDS * 1000)
  probe.measuring = false
  const seconds = (performance.now() - startedAt) / 1000
  clearInterval(ballSampler)
  return { before, after: counters(), seconds, ballsInFlight: ballTotal / Math.max(1, ballSamples) }
}

/** The two tables: time per tick (with the engine alone for comparison), then throughput. */
function printFigures (board, probe, { before, after, seconds, ballsInFlight }) {
  const engine = engineOnly(board, quick ? 600 : 1800)
  const tickStats = summarize(Float64Array.from(probe.ticks))
  const commitStats = summarize(Float64Array.from(probe.commits))
  const lagStats = summarize(Float64Array.from(probe.lags))
  const row = (name, s, note = '') => [name, fixed(s.p50, 2), fixed(s.p99, 2), fixed(s.max, 2), fixed(s.mean, 2), note]

  console.log(`\nServer ticks: ${int(ROOMS)} rooms × ${BALLS_PER_ROOM} balls (16 rows), 1 client per room, SQLite WAL + synchronous=FULL` +
    `${process.env.PLINKO_BENCH_PINNED ? ', pinned to CPU 0' : ''}; ${fixed(seconds, 1)} s measured after ${WARMUP_SECONDS} s warm-up${quick ? ' (--quick)' : ''}\n`)
  console.log(formatTable(
    [{ title: 'per tick (ms)', align: 'left' }, { title: 'p50' }, { title: 'p99' }, { title: 'max' }, { title: 'mean' }, { title: 'note', align: 'left' }],
    [
      row('tick: step rooms + snapshots', tickStats, `goal p99 < ${GOAL_P99_MS} ms: ${tickStats.p99 < GOAL_P99_MS ? 'met' : 'NOT met'}`),
      row('group commit (writer thread, until durable)', commitStats, `${int(probe.commits.length)} transactions`),
      row('tick lag (start vs. schedule)', lagStats, ''),
      row('engine alone, same load', engine, 'DropSimulator.step × 1,000')
    ]
  ))
  const ticks = after.ticks - before.ticks
  const drops = after.drops - before.drops
  console.log('\n' + formatTable(
    [{ title: 'throughput', align: 'left' }, { title: 'value' }],
    [
      ['ticks per second', fixed(ticks / seconds, 2)],
      ['ticks dropped (stalls > 10 ticks)', int(after.dropped - before.dropped)],
      ['balls in flight (mean)', int(ballsInFlight)],
      ['drops recorded per second', int(drops / seconds)],
      ['room frame bytes per second (all clients; snapshots + batched events)', bytes((after.snapshotBytes - before.snapshotBytes) / seconds)],
      ['own-event bytes per second (all clients; JSON)', bytes((after.eventBytes - before.eventBytes) / seconds)]
    ]
  ))
}

/** The engine's share: the same 10,000 balls stepped with nothing else. */
function engineOnly (board, ticks) {
  const simulators = Array.from({ length: ROOMS }, () => new DropSimulator(board))
  let nonce = 0
  const seed = () => deriveDropSeed('bench-server-seed', 'bench', nonce++)
  simulators.forEach((simulator, r) => { for (let b = 0; b < BALLS_PER_ROOM; b++) simulator.addDrop(seed(), r) })
  // Spread the balls over their flight first, as in a busy server.
  for (let t = 0; t < 300; t++) stepAll(simulators, seed)
  const samples = new Float64Array(ticks)
  for (let t = 0; t < ticks; t++) {
    const started = process.hrtime.bigint()
    stepAll(simulators, seed)
    samples[t] = Number(process.hrtime.bigint() - started) / 1e6
  }
  return summarize(samples)
}

function stepAll (simulators, seed) {
  for (const simulator of simulators) {
    const landed = simulator.step()
    for (let i = landed.length; i > 0; i--) simulator.addDrop(seed())
  }
}

function sum (items, key) {
  return items.reduce((total, item) => total + item[key], 0)
}

function sleep (ms) {
  return new Promise((resolve) => setTimeout(resolve, ms))
}

/** "On one core": re-run under taskset -c 0 when it is available. */
function pinToOneCore () {
  if (process.env.PLINKO_BENCH_PINNED || process.env.PLINKO_BENCH_NO_PIN) return
  if (spawnSync('taskset', ['-V'], { stdio: 'ignore' }).status !== 0) return
  const child = spawnSync('taskset', ['-c', '0', process.execPath, ...process.execArgv, fileURLToPath(import.meta.url), ...process.argv.slice(2)], {
    stdio: 'inherit',
    env: { ...process.env, PLINKO_BENCH_PINNED: '1' }
  })
  process.exit(child.status ?? 1)
}
