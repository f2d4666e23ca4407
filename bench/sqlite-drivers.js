/**
 * The SQLite ledger on node:sqlite (what the server uses) beside the same
 * store on better-sqlite3 (what it used before), in one run, on the same
 * machine and the same code: better-sqlite3 replaces `node:sqlite` through
 * bench/better-sqlite3-hooks.js, so only the driver differs.
 *
 *   npm install --prefix <dir outside the project> better-sqlite3@12
 *   BETTER_SQLITE3_DIR=<that dir> node bench/sqlite-drivers.js [--seconds 10] [--rounds 2] [--restarts 5]
 *
 * Without BETTER_SQLITE3_DIR it measures node:sqlite alone. Nothing is
 * installed by the bench. Three figures per driver:
 * - commit latency p50/p99: the group commit's pattern (one transaction per
 *   60 Hz tick, ticks merged while one is being written) at the capacity
 *   run's write rate: 750 new drops/s and as many settlements (each 180
 *   ticks after its drop), 1,500 players; from the end of a tick to its
 *   transaction's durable commit (synchronous=FULL), on the writer thread.
 * - CPU per committed drop: the process's CPU (event loop + writer thread)
 *   for the same ticks committed back to back, one transaction each (so the
 *   work does not depend on how many ticks a busy machine merged), divided
 *   by the drops committed.
 * - recovery after SIGKILL: a real server process (server/server.js) is
 *   killed with 100 balls in flight; on a copy of its ledger per driver, the
 *   recovery (open, migrate, replay and settle the 100, durably), and a
 *   real server restarted on another copy (spawn to listening).
 * The drivers run alternately (`--rounds`, in alternating order), in child
 * processes. The figures move a lot with the machine's load: compare the
 * round-by-round ratios it prints last.
 */
import { spawn } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { DatabaseSync } from 'node:sqlite'
import WebSocket from 'ws'
import { startServerProcess } from '../tools/server-process.js'
import { LIFTED_LIMITS } from '../tools/lifted-limits.js'
import { formatTable } from './table.js'

const HOOKS = fileURLToPath(new URL('./better-sqlite3-hooks.js', import.meta.url))
const SELF = fileURLToPath(import.meta.url)
const TICK_HZ = 60
const DROPS_PER_SECOND = 750
const FLIGHT_TICKS = 180
const PLAYERS = 1500
const WARMUP_TICKS = FLIGHT_TICKS + 60
const IN_FLIGHT_AT_KILL = 100

const args = process.argv.slice(2)
const option = (name, fallback) => {
  const at = args.indexOf(`--${name}`)
  return at === -1 ? fallback : args[at + 1]
}

if (option('child') === 'commit') await commitChild(Number(option('seconds', 10)), option('paced', 'yes') === 'yes')
else if (option('child') === 'recover') await recoverChild(option('file'))
else await main()

async function main () {
  const seconds = Number(option('seconds', 10))
  const rounds = Number(option('rounds', 2))
  const restarts = Number(option('restarts', 5))
  const bsqDir = process.env.BETTER_SQLITE3_DIR
  const drivers = [{ name: 'node:sqlite', env: { NODE_OPTIONS: '' } }]
  if (bsqDir) drivers.push({ name: 'better-sqlite3', env: { NODE_OPTIONS: `--import=${HOOKS}`, BETTER_SQLITE3_DIR: path.resolve(bsqDir) } })
  else console.log('BETTER_SQLITE3_DIR is not set: node:sqlite alone (see the header of bench/sqlite-drivers.js)')
  console.log(`Node ${process.version}, SQLite ${process.versions.sqlite}; ${DROPS_PER_SECOND} drops/s + settlements at ${TICK_HZ} Hz, ${seconds} s × ${rounds} rounds per driver; ${restarts} kills with ${IN_FLIGHT_AT_KILL} in flight`)

  const results = new Map(drivers.map((d) => [d.name, { latencies: [], cpuUs: 0, drops: 0, maxMerged: 0, recovery: [], restart: [], version: '', roundP50s: [], roundCpus: [] }]))
  for (let round = 0; round < rounds; round++) {
    for (const driver of round % 2 === 0 ? drivers : [...drivers].reverse()) {
      const run = await runChild(driver, ['--child', 'commit', '--seconds', String(seconds)])
      const back = await runChild(driver, ['--child', 'commit', '--seconds', String(seconds), '--paced', 'no'])
      const r = results.get(driver.name)
      r.latencies.push(...run.latencies)
      r.cpuUs += back.cpuUs
      r.drops += back.drops
      r.maxMerged = Math.max(r.maxMerged, run.maxMerged)
      r.version = run.sqliteVersion
      r.roundP50s.push(percentile(run.latencies, 0.5))
      r.roundCpus.push(back.cpuUs / back.drops)
      console.log(`  ${driver.name} round ${round + 1}: ${run.drops} drops committed, p50 ${percentile(run.latencies, 0.5).toFixed(2)} ms, p99 ${percentile(run.latencies, 0.99).toFixed(2)} ms; back to back ${(back.cpuUs / back.drops).toFixed(1)} µs CPU per drop`)
    }
  }
  for (let i = 0; i < restarts; i++) {
    for (const [name, { recoveryMs, restartMs }] of await recoveryRound(i % 2 === 0 ? drivers : [...drivers].reverse())) {
      results.get(name).recovery.push(recoveryMs)
      results.get(name).restart.push(restartMs)
      console.log(`  ${name} kill ${i + 1}: ${IN_FLIGHT_AT_KILL} in flight settled in ${recoveryMs.toFixed(1)} ms; a server restarted on the same ledger listening after ${restartMs.toFixed(0)} ms`)
    }
  }

  const rows = [...results].map(([name, r]) => [
    `${name} (${r.version})`,
    percentile(r.latencies, 0.5).toFixed(2),
    percentile(r.latencies, 0.99).toFixed(2),
    String(r.maxMerged),
    (r.cpuUs / r.drops).toFixed(1),
    median(r.recovery).toFixed(1),
    median(r.restart).toFixed(0)
  ])
  console.log()
  const columns = ['driver (SQLite)', 'commit p50 ms', 'commit p99 ms', 'most ticks merged', 'CPU µs / drop', 'recovery after SIGKILL ms', 'restart to listening ms']
  console.log(formatTable(columns.map((title, i) => ({ title, align: i === 0 ? 'left' : 'right' })), rows))
  console.log('(restarts: medians; commit: every tick of every round)')
  if (results.size === 2) {
    const [a, b] = [...results.values()]
    const ratio = (x, y) => `${((x / y - 1) * 100).toFixed(0)}%`
    const paired = (x, y) => median(x.map((value, i) => value / y[i])).toFixed(2)
    console.log(`node:sqlite / better-sqlite3, round by round (each pair run back to back, in alternating order), median of the ratios: commit p50 ${paired(a.roundP50s, b.roundP50s)}, CPU per drop ${paired(a.roundCpus, b.roundCpus)}`)
    console.log(`node:sqlite vs better-sqlite3: commit p50 ${ratio(percentile(a.latencies, 0.5), percentile(b.latencies, 0.5))}, p99 ${ratio(percentile(a.latencies, 0.99), percentile(b.latencies, 0.99))}, CPU/drop ${ratio(a.cpuUs / a.drops, b.cpuUs / b.drops)}, recovery ${ratio(median(a.recovery), median(b.recovery))}, restart ${ratio(median(a.restart), median(b.restart))} (positive: node:sqlite slower)`)
  }
}

/** Runs this file as a child on `driver`; resolves with the JSON it prints last. */
function runChild (driver, childArgs) {
  return new Promise((resolve, reject) => {
    const child = spawn(process.execPath, [SELF, ...childArgs], { env: { ...process.env, ...driver.env }, stdio: ['ignore', 'pipe', 'inherit'] })
    let out = ''
    child.stdout.on('data', (chunk) => { out += chunk })
    child.once('exit', (code) => {
      if (code !== 0) return reject(new Error(`${driver.name} child exited ${code}: ${out}`))
      resolve(JSON.parse(out.trim().split('\n').pop()))
    })
  })
}

/**
 * One tick's rows at the capacity run's write rate: the drops released in
 * it, the settlements of those released FLIGHT_TICKS before, their nonces
 * and the net balance change per player.
 * @param {object} batch @param {number} tick
 * @param {{ nonces: number[], flying: Map<number, { id: number, playerId: string }[]>, nextDropId: number, due: number }} load
 */
function addTickRows (batch, tick, load) {
  const deltas = new Map()
  load.due += DROPS_PER_SECOND / TICK_HZ
  const released = []
  for (; load.due >= 1; load.due--) {
    const id = load.nextDropId++
    const p = id % PLAYERS
    const nonce = load.nonces[p]++
    batch.drops.push({ id, playerId: `p${p}`, room: `16-high-${p % 100}`, rows: 16, risk: 'high', engineVersion: '2.0.0', serverSeedId: `s${p}`, serverSeedHash: 'b'.repeat(64), clientSeed: 'client', nonce, dropSeed: 'd'.repeat(64), bet: 10, payoutRule: 2, startTick: tick, createdAt: Date.now() })
    batch.nonces.push({ seedId: `s${p}`, nextNonce: nonce + 1 })
    deltas.set(`p${p}`, (deltas.get(`p${p}`) ?? 0) - 10000)
    released.push({ id, playerId: `p${p}` })
  }
  load.flying.set(tick, released)
  for (const drop of load.flying.get(tick - FLIGHT_TICKS) ?? []) {
    batch.settlements.push({ id: drop.id, bucket: 8, multiplier: 0.2, payout: 2000, ticks: FLIGHT_TICKS, stateHash: '0'.repeat(16), settledAt: Date.now() })
    deltas.set(drop.playerId, (deltas.get(drop.playerId) ?? 0) + 2000)
  }
  load.flying.delete(tick - FLIGHT_TICKS)
  for (const [playerId, delta] of deltas) batch.balances.push({ playerId, delta })
  batch.players.push(...deltas.keys())
}

/**
 * The group commit's write pattern on a fresh ledger; prints { latencies,
 * cpuUs, drops, maxMerged, sqliteVersion }. Paced: on a 60 Hz clock, ticks
 * merged while a commit runs (latency). Not paced: the same ticks back to
 * back, each its own transaction, so the work per drop does not depend on
 * how busy the machine is (CPU per drop).
 */
async function commitChild (seconds, paced) {
  const { SqliteStore } = await import('../server/store/sqlite-store.js')
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-sqlite-drivers-'))
  const store = new SqliteStore({ file: path.join(dir, 'ledger.sqlite') })
  try {
    await store.migrate()
    addPlayers(store.db)
    const load = { nonces: new Array(PLAYERS).fill(0), flying: new Map(), nextDropId: 1, due: 0 }
    const latencies = []
    let open = null // ticks waiting for the commit in progress: { ends: number[], batch }
    let writing = false
    let measuring = false
    let committedDrops = 0
    let maxMerged = 0
    let cpuStart = null
    let lastCommit = Promise.resolve()

    const send = () => {
      const { ends, batch } = open
      open = null
      writing = true
      maxMerged = Math.max(maxMerged, ends.length)
      lastCommit = store.commitBatch(batch).then(() => {
        const now = performance.now()
        if (measuring) {
          for (const end of ends) latencies.push(now - end)
          committedDrops += batch.drops.length
        }
        writing = false
        if (open) send()
      }, (error) => { console.error(error); process.exit(1) })
    }

    const endTick = (tick) => {
      const batch = open?.batch ?? { drops: [], settlements: [], balances: [], nonces: [], clientSeeds: [], players: [] }
      addTickRows(batch, tick, load)
      open = { ends: [...(open?.ends ?? []), performance.now()], batch }
      if (!writing) send()
    }

    // A drift-free 60 Hz clock, like the server's tick scheduler.
    const ticks = WARMUP_TICKS + seconds * TICK_HZ
    const start = performance.now()
    for (let tick = 0; tick < ticks; tick++) {
      const wait = start + (tick + 1) * 1000 / TICK_HZ - performance.now()
      if (paced && wait > 0) await new Promise((resolve) => setTimeout(resolve, wait))
      if (tick === WARMUP_TICKS) { measuring = true; cpuStart = process.cpuUsage() }
      endTick(tick)
      if (!paced) await lastCommit
    }
    while (writing || open) await new Promise((resolve) => setTimeout(resolve, 1))
    const cpu = process.cpuUsage(cpuStart)
    const sqliteVersion = store.db.prepare('SELECT sqlite_version() AS v').get().v
    await store.close()
    process.stdout.write(JSON.stringify({ latencies, cpuUs: cpu.user + cpu.system, drops: committedDrops, maxMerged, sqliteVersion }) + '\n')
  } finally {
    fs.rmSync(dir, { recursive: true, force: true })
  }
}

/** The bench's players and their seeds, in one transaction on the store's own connection. */
function addPlayers (db) {
  const player = db.prepare('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES (?, ?, ?, ?, ?)')
  const seed = db.prepare('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES (?, ?, ?, ?, 1, 0, ?)')
  db.exec('BEGIN IMMEDIATE')
  for (let p = 0; p < PLAYERS; p++) {
    player.run(`p${p}`, `token-${p}`, 1e12, 'client', 0)
    seed.run(`s${p}`, `p${p}`, 'a'.repeat(64), `hash-${p}`, 0)
  }
  db.exec('COMMIT')
}

/**
 * A real server (on node:sqlite: the file is the same for both drivers)
 * killed with SIGKILL once IN_FLIGHT_AT_KILL of its drops are acknowledged
 * (none has landed yet). Then, for each driver, on its own copy of that
 * ledger: the recovery itself in a child (open, migrate, settle every drop
 * in flight, durably), and a real server restarted on another copy (spawn
 * to listening: Node's start and the server's modules included).
 * @returns {Promise<Map<string, { recoveryMs: number, restartMs: number }>>}
 */
async function recoveryRound (drivers) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-sqlite-recovery-'))
  const env = { ...LIFTED_LIMITS, OPERATOR_TOKEN: 'bench-operator-token-0123456789', CLIENT_DIR: path.join(dir, 'no-client'), DROP_RATE: '1000', DROP_BURST: String(IN_FLIGHT_AT_KILL), MAX_BALLS_PER_ROOM: '4096' }
  try {
    const killed = path.join(dir, 'killed.sqlite')
    const server = startServerProcess(`sqlite:${killed}`, { ...env, NODE_OPTIONS: '' })
    const port = await server.port
    const session = await (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
    await dropAndWait(port, session, IN_FLIGHT_AT_KILL)
    server.child.kill('SIGKILL')
    await server.exited
    const copy = (name) => {
      const file = path.join(dir, `${name}.sqlite`)
      for (const suffix of ['', '-wal', '-shm']) if (fs.existsSync(killed + suffix)) fs.copyFileSync(killed + suffix, file + suffix)
      return file
    }
    const figures = new Map()
    for (const driver of drivers) {
      const slug = driver.name.replace(/\W/g, '-')
      const file = copy(`${slug}-recover`)
      const inFlight = countInFlight(file)
      if (inFlight !== IN_FLIGHT_AT_KILL) throw new Error(`${inFlight} drops in flight at the kill, not ${IN_FLIGHT_AT_KILL}`)
      const { recoveryMs, settled } = await runChild(driver, ['--child', 'recover', '--file', file])
      if (settled !== inFlight || countInFlight(file) !== 0) throw new Error(`${driver.name}: recovery settled ${settled} of ${inFlight}`)
      const restartFile = copy(`${slug}-restart`)
      const started = performance.now()
      const restarted = startServerProcess(`sqlite:${restartFile}`, { ...env, ...driver.env })
      await restarted.port
      const restartMs = performance.now() - started
      if (!/settled drops interrupted by the last shutdown/.test(restarted.output()) || countInFlight(restartFile) !== 0) throw new Error(`the restarted server settled nothing:\n${restarted.output()}`)
      restarted.child.kill('SIGTERM')
      await restarted.exited
      figures.set(driver.name, { recoveryMs, restartMs })
    }
    return figures
  } finally {
    fs.rmSync(dir, { recursive: true, force: true })
  }
}

/** Opens a killed ledger as the server does and settles what was in flight; prints { recoveryMs, settled }. */
async function recoverChild (file) {
  const { openStore } = await import('../server/store/open-store.js')
  const { settleInterruptedDrops } = await import('../server/game/recovery.js')
  const log = { info () {}, warn () {}, error () {} }
  const started = performance.now()
  const store = await openStore({ kind: 'sqlite', file, busyTimeoutMs: 5000 })
  const { settled } = await settleInterruptedDrops(store, log)
  const recoveryMs = performance.now() - started
  await store.close()
  process.stdout.write(JSON.stringify({ recoveryMs, settled }) + '\n')
}

/** Joins a 16-row room and drops `count` balls; resolves once every one is acknowledged (`dropped`). */
function dropAndWait (port, session, count) {
  return new Promise((resolve, reject) => {
    const socket = new WebSocket(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
    let acked = 0
    socket.on('error', reject)
    socket.on('message', (data, isBinary) => {
      if (isBinary) return
      const message = JSON.parse(data.toString())
      if (message.type === 'welcome') socket.send(JSON.stringify({ type: 'join', room: '16-high' }))
      else if (message.type === 'joined') for (let i = 0; i < count; i++) socket.send(JSON.stringify({ type: 'drop', bet: 1 }))
      else if (message.type === 'dropped' && message.player === session.playerId && ++acked === count) { socket.terminate(); resolve() }
      else if (message.type === 'error') reject(new Error(`server refused: ${JSON.stringify(message)}`))
    })
  })
}

function countInFlight (file) {
  const db = new DatabaseSync(file, { readOnly: true })
  try {
    return db.prepare("SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'").get().n
  } finally {
    db.close()
  }
}

function percentile (values, q) {
  if (values.length === 0) return NaN
  const sorted = [...values].sort((a, b) => a - b)
  return sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))]
}

function median (values) {
  return percentile(values, 0.5)
}
