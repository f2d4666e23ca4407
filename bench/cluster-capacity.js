#!/usr/bin/env node
/**
 * node bench/cluster-capacity.js [--step 250] [--max 3000] [--hold 10] [--interval 2000]
 *
 * Players held by 1 server process vs 2 clustered ones on this machine.
 * Starts a throwaway PostgreSQL and Redis (the test helpers), then for each
 * mode adds players in steps (each: session, WebSocket, join one of the 27
 * rooms round robin — following E_WRONG_NODE — and a drop of 1 credit
 * every --interval ms at a random phase), holds each step --hold seconds and
 * measures, client side, drop → own `dropped` latency. A step is held when
 * its p99 stays under 300 ms with no error and no drop left unanswered.
 * The load generator runs in this process, on the same CPUs as the servers.
 */
import { spawn } from 'node:child_process'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { fileURLToPath } from 'node:url'
import WebSocket from 'ws'
import { startPostgres } from '../tools/postgres-process.js'
import { freePort } from '../tools/free-port.js'
import { startRedis } from '../tools/redis-process.js'
import { ROOM_IDS } from '../protocol/room-id.js'
import { LIFTED_LIMITS } from '../tools/lifted-limits.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')
const { values } = parseArgs({ options: { step: { type: 'string', default: '250' }, max: { type: 'string', default: '3000' }, hold: { type: 'string', default: '10' }, interval: { type: 'string', default: '2000' } } })
const STEP = Number(values.step); const MAX = Number(values.max); const HOLD_S = Number(values.hold); const INTERVAL = Number(values.interval)
const P99_LIMIT_MS = 300
/** One room per board, as when the README's figures were measured. */
const ROOMS = ROOM_IDS.slice(0, 27)

async function startServer (env) {
  const port = await freePort()
  const child = spawn(process.execPath, [path.join(ROOT, 'server/server.js')], {
    cwd: ROOT,
    env: { ...process.env, PORT: String(port), HOST: '127.0.0.1', LOG_LEVEL: 'warn', OPERATOR_TOKEN: 'operator-token-for-bench-0123456789', CLIENT_DIR: '/nonexistent', ...LIFTED_LIMITS, ...env, PUBLIC_URL: env.REDIS_URL ? `http://127.0.0.1:${port}` : '' },
    stdio: ['ignore', 'inherit', 'inherit']
  })
  const url = `http://127.0.0.1:${port}`
  for (let i = 0; i < 300; i++) {
    try { if ((await fetch(url + '/api/health')).ok) break } catch {}
    await new Promise((resolve) => setTimeout(resolve, 50))
  }
  return { url, stop: () => new Promise((resolve) => { child.once('exit', resolve); child.kill('SIGTERM') }) }
}

function player (entry, room, stats) {
  return new Promise((resolve, reject) => {
    fetch(entry + '/api/session', { method: 'POST' }).then((r) => r.json()).then(({ token }) => {
      let timer = null
      let seq = 0
      let joinedOnce = false
      let redirecting = false
      const pending = new Map()
      const open = (base) => {
        const socket = new WebSocket(`${base.replace(/^http/, 'ws')}/ws?token=${token}`)
        socket.on('message', (data, isBinary) => {
          if (isBinary) return
          const m = JSON.parse(data)
          if (m.type === 'welcome') socket.send(JSON.stringify({ type: 'join', room, ref: 'j' }))
          else if (m.type === 'joined' && m.ref === 'j') {
            joinedOnce = true
            resolve({ close: () => { clearInterval(timer); socket.close() }, pending })
            setTimeout(() => {
              timer = setInterval(() => {
                const ref = ++seq
                pending.set(ref, performance.now())
                socket.send(JSON.stringify({ type: 'drop', bet: 1, ref }))
              }, INTERVAL)
            }, Math.random() * INTERVAL)
          } else if (m.type === 'error' && m.ref === 'j' && m.code === 'E_WRONG_NODE') {
            redirecting = true; socket.close(); open(m.owner)
          } else if (m.type === 'error' && m.ref === 'j') {
            setTimeout(() => socket.send(JSON.stringify({ type: 'join', room, ref: 'j' })), m.retryAfterMs ?? 200)
          } else if (m.type === 'dropped' && m.ref !== undefined && pending.has(m.ref)) {
            stats.latencies.push(performance.now() - pending.get(m.ref)); pending.delete(m.ref)
          } else if (m.type === 'error') {
            stats.errors++; if (m.ref !== undefined) pending.delete(m.ref)
          }
        })
        socket.on('error', (error) => { stats.errors++; reject(error) })
        socket.on('close', (code, reason) => {
          clearInterval(timer)
          if (!joinedOnce && !redirecting) reject(new Error(`closed before joining: ${code} ${reason}`))
          redirecting = false
        })
      }
      open(entry)
    }, reject)
  })
}

async function measure (label, entries) {
  const players = []
  let held = 0
  const rows = []
  // One stats object for every player of the run; each step measures a fresh window.
  const stats = { latencies: [], errors: 0 }
  for (let target = STEP; target <= MAX; target += STEP) {
    const adding = []
    for (let i = players.length; i < target; i++) adding.push(player(entries[i % entries.length], ROOMS[i % ROOMS.length], stats))
    players.push(...await Promise.all(adding))
    // Settle in, then measure.
    await new Promise((resolve) => setTimeout(resolve, INTERVAL + 1000))
    const window = { latencies: [] }
    stats.latencies = window.latencies
    for (const p of players) p.pending.clear()
    const before = stats.errors
    await new Promise((resolve) => setTimeout(resolve, HOLD_S * 1000))
    const now = performance.now()
    const stuck = players.reduce((n, p) => n + [...p.pending.values()].filter((t) => now - t > 2000).length, 0)
    const sorted = window.latencies.sort((a, b) => a - b)
    const p99 = sorted[Math.floor(sorted.length * 0.99)] ?? Infinity
    const p50 = sorted[Math.floor(sorted.length * 0.5)] ?? Infinity
    const errors = stats.errors - before
    const ok = p99 < P99_LIMIT_MS && errors === 0 && stuck === 0
    rows.push({ label, players: target, drops: sorted.length, p50: p50.toFixed(1), p99: p99.toFixed(1), errors, stuck, ok })
    console.log(JSON.stringify(rows.at(-1)))
    if (!ok) break
    held = target
  }
  for (const p of players) p.close()
  return { held, rows }
}

const postgres = await startPostgres()
const redis = await startRedis()
const results = {}
try {
  const db1 = await postgres.createDatabase()
  const one = await startServer({ DATABASE_URL: db1 })
  results.one = await measure('1 process', [one.url])
  await one.stop()
  const db2 = await postgres.createDatabase()
  const a = await startServer({ DATABASE_URL: db2, REDIS_URL: redis.url })
  const b = await startServer({ DATABASE_URL: db2, REDIS_URL: redis.url })
  results.two = await measure('2 processes', [a.url, b.url])
  await a.stop(); await b.stop()
} finally {
  await redis.stop()
  await postgres.stop()
}
console.log(`players held: 1 process ${results.one.held}, 2 processes ${results.two.held}, ratio ${(results.two.held / Math.max(1, results.one.held)).toFixed(2)}`)
process.exit(0)
