#!/usr/bin/env node
/**
 * Soak: runs the real server (node server/server.js, a child process on a
 * fresh SQLite ledger unless --database is given) under a steady load —
 * PLAYERS WebSocket players spread over the rooms, each dropping RATE balls
 * per second — for DURATION, sampling the server's memory (RSS, heap used)
 * and tick duration from its /metrics every INTERVAL. Prints each sample,
 * then the least-squares slope of each series after the warm-up (the first
 * fifth of the run) and whether it is flat; then stops the server with
 * SIGTERM and checks the ledger: every acknowledged drop recorded once and
 * settled, every balance = start + payouts − bets.
 *
 *   node scripts/soak.js                       # 10 minutes, 200 players, 1 drop/s each
 *   node scripts/soak.js --duration 60s --players 50 --rate 2 --json
 *
 * The last line of output is a JSON summary. Exit code 0 when nothing was
 * lost (and, with --strict, when memory and tick duration are flat too).
 * k6 load and soak scenarios live in loadtest/; this script needs no k6.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { DatabaseSync } from 'node:sqlite'
import WebSocket from 'ws'
import { createBoard, simulateDrop } from '../engine/index.js'
import { payoutFor } from '../server/game/money.js'
import { ROOM_IDS } from '../protocol/room-id.js'
import { startServerProcess } from '../tools/server-process.js'
import { LIFTED_LIMITS } from '../tools/lifted-limits.js'

const OPERATOR_TOKEN = 'soak-operator-token-0123456789abcdef'
const START = 100000

/**
 * Flat: the trend (least-squares slope × the measured span) raises a series
 * by less than 10% of its mean, or by less than an absolute floor (noise:
 * GC and allocator sawtooth on short runs). A soak looks for growth: a
 * series that falls is flat for this purpose (and reported as falling).
 */
const FLAT_FLOOR = { rssMb: 8, heapMb: 4, tickMs: 0.1 }

const { values: args } = parseArgs({
  options: {
    duration: { type: 'string', default: '10m' },
    players: { type: 'string', default: '200' },
    rate: { type: 'string', default: '1' },
    interval: { type: 'string', default: '5s' },
    database: { type: 'string' },
    json: { type: 'boolean', default: false },
    strict: { type: 'boolean', default: false }
  }
})
const durationMs = parseDuration(args.duration)
const intervalMs = parseDuration(args.interval)
const playerCount = Number(args.players)
const ratePerPlayer = Number(args.rate)

function parseDuration (text) {
  const match = /^(\d+(?:\.\d+)?)(ms|s|m|h)?$/.exec(text)
  if (!match) throw new Error(`bad duration ${text}: use e.g. 90s, 10m`)
  return Number(match[1]) * { ms: 1, s: 1000, m: 60_000, h: 3_600_000 }[match[2] ?? 's']
}

const log = (line) => { if (!args.json) console.log(line) }
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms))

const tempDir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-soak-'))
const databaseUrl = args.database ?? `sqlite:${path.join(tempDir, 'ledger.sqlite')}`

function startServer () {
  return startServerProcess(databaseUrl, {
    OPERATOR_TOKEN,
    STARTING_BALANCE: String(START),
    ...LIFTED_LIMITS,
    CLIENT_DIR: path.join(tempDir, 'no-client')
  })
}

/** One player: a session, a socket, a room; drops at a steady rate and counts what it is told. */
async function startPlayer (base, index, stats) {
  const session = await (await fetch(`${base}/api/session`, { method: 'POST' })).json()
  const socket = new WebSocket(`${base.replace('http', 'ws')}/ws?token=${session.token}`)
  const player = { session, socket, acked: new Set(), timer: null, closeCode: null }
  socket.on('message', (data, isBinary) => {
    if (isBinary) { stats.snapshots++; return }
    const message = JSON.parse(data.toString())
    if (message.player !== session.playerId && message.type !== 'error') return
    if (message.type === 'dropped') player.acked.add(message.dropId)
    else if (message.type === 'settled') stats.settled++
    else if (message.type === 'error') stats.errors.set(message.code, (stats.errors.get(message.code) ?? 0) + 1)
  })
  socket.on('close', (code) => { player.closeCode = code })
  await new Promise((resolve, reject) => { socket.once('open', resolve); socket.once('error', reject) })
  socket.send(JSON.stringify({ type: 'join', room: ROOM_IDS[index % ROOM_IDS.length] }))
  const everyMs = 1000 / ratePerPlayer
  // Spread the players' drops over the interval so the load is steady, not in bursts.
  player.timer = setTimeout(() => {
    player.timer = setInterval(() => {
      if (socket.readyState !== WebSocket.OPEN) return
      socket.send(JSON.stringify({ type: 'drop', bet: 1 + Math.floor(Math.random() * 20) }))
      stats.sent++
    }, everyMs)
  }, Math.random() * everyMs)
  return player
}

/** The metrics this script follows, from Prometheus text. */
async function readMetrics (base) {
  const text = await (await fetch(`${base}/metrics`, { headers: { authorization: `Bearer ${OPERATOR_TOKEN}` } })).text()
  const value = (name) => Number(new RegExp(`^${name} (\\S+)$`, 'm').exec(text)?.[1] ?? NaN)
  return {
    rss: value('plinko_process_resident_memory_bytes'),
    heap: value('plinko_nodejs_heap_size_used_bytes'),
    tickSum: value('plinko_tick_duration_seconds_sum'),
    tickCount: value('plinko_tick_duration_seconds_count'),
    lagSum: value('plinko_tick_lag_seconds_sum'),
    lagCount: value('plinko_tick_lag_seconds_count'),
    balls: value('plinko_balls_in_flight'),
    drops: value('plinko_drops_total')
  }
}

/** Least-squares slope of y over x. */
function slope (points) {
  const n = points.length
  if (n < 2) return NaN
  const mx = points.reduce((s, p) => s + p[0], 0) / n
  const my = points.reduce((s, p) => s + p[1], 0) / n
  let num = 0
  let den = 0
  for (const [x, y] of points) { num += (x - mx) * (y - my); den += (x - mx) ** 2 }
  return num / den
}

/** Every drop settled from its seed, once; every balance = start + payouts − bets. */
function checkLedger (file, players) {
  const db = new DatabaseSync(file, { readOnly: true })
  try {
    const rows = db.prepare('SELECT id, player_id, rows, risk, engine_version, drop_seed, bet, status, payout, payout_rule FROM drops').all()
    const boards = new Map()
    const problems = []
    // The ledger holds balances and payouts in milli-credits, bets in whole credits.
    const balances = new Map(players.map((p) => [p.session.playerId, START * 1000]))
    const ids = new Set()
    for (const row of rows) {
      ids.add(Number(row.id))
      const key = `${row.rows}-${row.risk}@${row.engine_version}`
      if (!boards.has(key)) boards.set(key, createBoard({ rows: row.rows, risk: row.risk, engineVersion: row.engine_version }))
      const expected = payoutFor(Number(row.bet), simulateDrop(boards.get(key), row.drop_seed).multiplier, Number(row.payout_rule))
      if (row.status !== 'settled' || Number(row.payout) !== expected) problems.push(`drop ${row.id}: ${row.status}, payout ${row.payout}, expected ${expected}`)
      if (balances.has(row.player_id)) balances.set(row.player_id, balances.get(row.player_id) - Number(row.bet) * 1000 + Number(row.payout))
    }
    let acked = 0
    for (const player of players) {
      for (const id of player.acked) { acked++; if (!ids.has(id)) problems.push(`acknowledged drop ${id} missing`) }
      const stored = Number(db.prepare('SELECT balance FROM players WHERE id = ?').get(player.session.playerId).balance)
      if (stored !== balances.get(player.session.playerId)) problems.push(`balance of ${player.session.playerId}: ${stored} != ${balances.get(player.session.playerId)}`)
    }
    return { drops: rows.length, acked, problems }
  } finally {
    db.close()
  }
}

async function main () {
  const server = startServer()
  const port = await server.port
  const base = `http://127.0.0.1:${port}`
  const stats = { sent: 0, settled: 0, snapshots: 0, errors: new Map() }
  log(`soak: ${playerCount} players × ${ratePerPlayer} drop/s for ${args.duration} on ${databaseUrl.startsWith('sqlite:') ? 'SQLite' : 'PostgreSQL'} (server pid ${server.child.pid})`)
  const players = []
  for (let i = 0; i < playerCount; i++) players.push(await startPlayer(base, i, stats))

  const samples = []
  const started = Date.now()
  let previous = await readMetrics(base)
  log('   t(s)   RSS(MB)  heap(MB)  tick(ms)  lag(ms)  balls  drops')
  while (Date.now() - started < durationMs) {
    await sleep(Math.min(intervalMs, durationMs - (Date.now() - started)))
    const now = await readMetrics(base)
    const ticks = now.tickCount - previous.tickCount
    const sample = {
      t: (Date.now() - started) / 1000,
      rssMb: now.rss / 2 ** 20,
      heapMb: now.heap / 2 ** 20,
      tickMs: ticks > 0 ? (now.tickSum - previous.tickSum) / ticks * 1000 : NaN,
      lagMs: now.lagCount > previous.lagCount ? (now.lagSum - previous.lagSum) / (now.lagCount - previous.lagCount) * 1000 : NaN,
      balls: now.balls,
      drops: now.drops
    }
    samples.push(sample)
    previous = now
    log(`${sample.t.toFixed(0).padStart(7)} ${sample.rssMb.toFixed(1).padStart(9)} ${sample.heapMb.toFixed(1).padStart(9)} ${sample.tickMs.toFixed(3).padStart(9)} ${sample.lagMs.toFixed(2).padStart(8)} ${String(sample.balls).padStart(6)} ${String(sample.drops).padStart(6)}`)
  }

  for (const player of players) { clearTimeout(player.timer); clearInterval(player.timer) }
  // A graceful stop settles what is in flight, so the ledger can be checked in full.
  server.child.kill('SIGTERM')
  const exit = await server.exited
  const warm = samples.filter((s) => s.t >= durationMs / 1000 / 5)
  const perMin = (key) => slope(warm.map((s) => [s.t / 60, s[key]]))
  const mean = (key) => warm.reduce((sum, x) => sum + x[key], 0) / warm.length
  const spanMin = warm.length > 1 ? (warm.at(-1).t - warm[0].t) / 60 : 0
  const trend = { rssMbPerMin: perMin('rssMb'), heapMbPerMin: perMin('heapMb'), tickMsPerMin: perMin('tickMs') }
  const limits = Object.fromEntries(Object.entries(FLAT_FLOOR).map(([key, floor]) => [key, Math.max(floor, 0.1 * mean(key))]))
  const drift = (key) => trend[`${key}PerMin`] * spanMin
  const flat = Object.fromEntries(Object.keys(FLAT_FLOOR).map((key) => [key, drift(key) < limits[key]]))
  const label = (key) => drift(key) < -limits[key] ? 'falling' : (flat[key] ? 'flat' : 'GROWING')
  const ledger = databaseUrl.startsWith('sqlite:') ? checkLedger(databaseUrl.slice('sqlite:'.length), players) : null
  const summary = {
    durationS: durationMs / 1000,
    players: playerCount,
    dropsPerSecond: playerCount * ratePerPlayer,
    dropsSent: stats.sent,
    dropsAcknowledged: players.reduce((n, p) => n + p.acked.size, 0),
    settledSeen: stats.settled,
    errors: Object.fromEntries(stats.errors),
    samples: samples.length,
    rssMb: { first: warm[0]?.rssMb, last: warm.at(-1)?.rssMb, max: Math.max(...samples.map((s) => s.rssMb)) },
    heapMb: { first: warm[0]?.heapMb, last: warm.at(-1)?.heapMb, max: Math.max(...samples.map((s) => s.heapMb)) },
    tickMs: { mean: mean('tickMs'), max: Math.max(...samples.map((s) => s.tickMs)) },
    trend,
    flat,
    serverExit: exit,
    ledger
  }
  const lost = !ledger || ledger.problems.length > 0 || exit.code !== 0
  log(`\nafter warm-up: RSS ${trend.rssMbPerMin.toFixed(3)} MB/min (${label('rssMb')}), heap ${trend.heapMbPerMin.toFixed(3)} MB/min (${label('heapMb')}), tick ${trend.tickMsPerMin.toFixed(4)} ms/min (${label('tickMs')}); mean tick ${summary.tickMs.mean.toFixed(3)} ms`)
  if (ledger) log(`ledger: ${ledger.drops} drops recorded, ${ledger.acked} acknowledged, ${ledger.problems.length === 0 ? 'all settled from their seeds, balances exact, nothing lost' : `${ledger.problems.length} PROBLEMS: ${ledger.problems.slice(0, 5).join('; ')}`}`)
  console.log(JSON.stringify(summary))
  for (const player of players) player.socket.terminate()
  if (!args.database) fs.rmSync(tempDir, { recursive: true, force: true })
  process.exitCode = lost || (args.strict && !Object.values(flat).every(Boolean)) ? 1 : 0
}

main().catch((error) => {
  console.error(error)
  process.exitCode = 1
})
