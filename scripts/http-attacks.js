#!/usr/bin/env node
import { spawn } from 'node:child_process'
import fs from 'node:fs'
import net from 'node:net'
import os from 'node:os'
import path from 'node:path'
import WebSocket from 'ws'
import { startServerProcess } from '../tools/server-process.js'
import { freePort } from '../tools/free-port.js'
import { eventually } from '../tools/eventually.js'

/**
 * The HTTP attacks of issue #21, bounded and on 127.0.0.1 only, against a
 * real server process (`node server/server.js`, default limits) on a fresh
 * SQLite file; prints one line of figures per attack. Loopback has all of
 * 127.0.0.0/8, so the attacker and the honest client use different
 * addresses (127.0.0.2.. and 127.0.0.1), as they would in production.
 *
 *   node scripts/http-attacks.js guess       wrong operator tokens for 10 s, one address: 403 vs 429
 *   node scripts/http-attacks.js slowloris   3,000 slow-header connections from one address, then 6,000 from 30, against
 *                                            a server that may open 2,048 files, with honest /api/health probes
 *   node scripts/http-attacks.js probes      /api/health and /metrics flooded from one address while a player pings
 *
 * `--root DIR` runs another checkout's server (to measure before a fix); NAME=value arguments set its environment.
 */
const OPERATOR_TOKEN = 'operator-token-for-attack-runs-0123456789'
const args = process.argv.slice(2)
const attack = args[0]
const root = args.includes('--root') ? path.resolve(args[args.indexOf('--root') + 1]) : undefined
/** NAME=value arguments: the server's environment (e.g. `probes MONITORING_PORT=0`, to flood a public port that has no /api/health). */
const serverEnv = Object.fromEntries(args.filter((arg) => /^[A-Z][A-Z0-9_]*=/.test(arg)).map((arg) => [arg.slice(0, arg.indexOf('=')), arg.slice(arg.indexOf('=') + 1)]))

const percentile = (values, p) => {
  if (values.length === 0) return NaN
  const sorted = [...values].sort((a, b) => a - b)
  return sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))]
}
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms))

/**
 * A server process for one attack. `nofile`: its open-file limit (prlimit), so that a few
 * thousand connections reach it as 22,000 reached the 20,000 of the issue's run.
 */
async function withServer (env, run, { nofile } = {}) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-attack-'))
  // LOG_LEVEL=warn (a log line per request would be part of the cost): the port is chosen here, not read from the log.
  const port = await freePort()
  const databaseUrl = `sqlite:${path.join(dir, 'ledger.sqlite')}`
  const variables = { OPERATOR_TOKEN, LOG_LEVEL: 'warn', PORT: String(port), ...env }
  const server = nofile
    ? prlimitedServer(nofile, databaseUrl, variables)
    : startServerProcess(databaseUrl, variables, root ? { root } : {})
  server.port?.catch(() => {})
  try {
    await eventually(async () => (await fetch(`http://127.0.0.1:${port}/api/rooms`).catch(() => null))?.ok, { intervalMs: 100 })
    return await run(`http://127.0.0.1:${port}`, port)
  } finally {
    server.child.kill('SIGTERM')
    await server.exited
    fs.rmSync(dir, { recursive: true, force: true })
  }
}

function prlimitedServer (nofile, databaseUrl, env) {
  const serverRoot = root ?? path.resolve(path.dirname(new URL(import.meta.url).pathname), '..')
  const child = spawn('prlimit', [`--nofile=${nofile}:${nofile}`, process.execPath, path.join(serverRoot, 'server/server.js')], {
    cwd: serverRoot,
    env: { ...process.env, DATABASE_URL: databaseUrl, HOST: '127.0.0.1', ...env },
    stdio: ['ignore', 'inherit', 'inherit']
  })
  return { child, exited: new Promise((resolve) => child.once('exit', resolve)) }
}

/** GET over a fresh connection from `localAddress`; resolves with status (0 = failed) and ms. */
function rawGet (port, pathname, { localAddress = '127.0.0.1', headers = {}, timeoutMs = 5000 } = {}) {
  return new Promise((resolve) => {
    const started = performance.now()
    const socket = net.connect({ port, host: '127.0.0.1', localAddress })
    let received = ''
    const done = (status) => { socket.destroy(); clearTimeout(timer); resolve({ status, ms: performance.now() - started }) }
    const timer = setTimeout(() => done(0), timeoutMs)
    socket.on('connect', () => socket.write(`GET ${pathname} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n${Object.entries(headers).map(([k, v]) => `${k}: ${v}\r\n`).join('')}\r\n`))
    socket.on('data', (chunk) => {
      received += chunk
      const match = /^HTTP\/1\.1 (\d+)/.exec(received)
      if (match) done(Number(match[1]))
    })
    socket.on('error', () => done(0))
    socket.on('close', () => done(0))
  })
}

async function guess () {
  await withServer({}, async (base) => {
    const counts = {}
    const deadline = Date.now() + 10_000
    let sent = 0
    // 16 keep-alive clients from one address, as fast as the server answers.
    await Promise.all(Array.from({ length: 16 }, async (_, worker) => {
      while (Date.now() < deadline) {
        const response = await fetch(`${base}/api/audit/drops`, { headers: { authorization: `Bearer guess-${worker}-${sent++}` } })
        await response.arrayBuffer()
        counts[response.status] = (counts[response.status] ?? 0) + 1
      }
    }))
    const right = await fetch(`${base}/api/audit/drops`, { headers: { authorization: `Bearer ${OPERATOR_TOKEN}` } })
    const metrics = await (await fetch(`${base}/metrics`)).text()
    const sample = (name) => /\{kind="operator"\} (\d+)/.exec(metrics.split('\n').filter((l) => l.startsWith(name)).join('\n'))?.[1] ?? 'n/a'
    console.log(`guess: ${sent} wrong operator tokens in 10 s from one address → ${Object.entries(counts).map(([s, n]) => `${n}×${s}`).join(', ')}; ` +
      `then the right token from that address → ${right.status} (Retry-After ${right.headers.get('retry-after') ?? '-'} s); ` +
      `/metrics: plinko_auth_failures_total ${sample('plinko_auth_failures_total')}, plinko_auth_throttled_total ${sample('plinko_auth_throttled_total')}`)
  })
}

/** Slow senders: each writes half a request, then one header byte a second, until closed. */
function slowSenders (port, count, addressOf) {
  const sockets = []
  let closed = 0
  for (let i = 0; i < count; i++) {
    const socket = net.connect({ port, host: '127.0.0.1', localAddress: addressOf(i) })
    socket.on('error', () => {})
    socket.on('connect', () => socket.write('GET /api/health HTTP/1.1\r\nHost: x\r\n'))
    socket.on('close', () => { closed++ })
    sockets.push(socket)
  }
  const drip = setInterval(() => { for (const socket of sockets) if (!socket.destroyed) socket.write('X') }, 1000)
  return { closed: () => closed, stop () { clearInterval(drip); for (const socket of sockets) socket.destroy() } }
}

async function probeWhile (port, seconds) {
  const probes = []
  const deadline = Date.now() + seconds * 1000
  while (Date.now() < deadline) {
    probes.push(await rawGet(port, '/api/health'))
    await sleep(100)
  }
  const ok = probes.filter((p) => p.status === 200)
  return `${ok.length}/${probes.length} honest probes 200 (p50 ${percentile(ok.map((p) => p.ms), 0.5).toFixed(1)} ms, p99 ${percentile(ok.map((p) => p.ms), 0.99).toFixed(1)} ms, max ${Math.max(...ok.map((p) => p.ms)).toFixed(1)} ms)`
}

async function slowloris () {
  // The server may open 2,048 files: 3,000 or 6,000 slow senders go past it, as 22,000 went past 20,000.
  for (const [label, count, addressOf] of [
    ['3,000 from one address', 3000, () => '127.0.0.2'],
    ['6,000 from 30 addresses', 6000, (i) => `127.0.2.${1 + (i % 30)}`]
  ]) {
    await withServer({}, async (base, port) => {
      const attack = slowSenders(port, count, addressOf)
      await sleep(500)
      // Held connections, 3 s in (before HTTP_HEADERS_TIMEOUT_MS closes the slow senders).
      const held = sleep(2500).then(() => rawGet(port, '/metrics', { localAddress: '127.0.0.3' }).then(() => fetch(`${base}/metrics`)).then((r) => r.text())).catch(() => '')
      const probes = await probeWhile(port, 15)
      const metrics = await (await fetch(`${base}/metrics`)).text()
      const line = (text, name) => text.split('\n').filter((l) => l.startsWith(name) && !l.startsWith('# ')).map((l) => l.replace(name, '').trim()).join(' ') || 'n/a'
      console.log(`slowloris, ${label}: ${probes}; server-side connections 3 s in: ${line(await held, 'plinko_http_connections ')}; attacker sockets closed by the server after 15 s: ${attack.closed()}/${count}; ` +
        `shed ${line(metrics, 'plinko_http_connections_shed_total')}; refused ${line(metrics, 'plinko_http_connections_refused_total')}`)
      attack.stop()
    }, { nofile: 2048 })
  }
}

/** An honest player in a room pings every 20 ms; returns its round trips. */
async function pingingPlayer (base, port, seconds) {
  const session = await (await fetch(`${base}/api/session`, { method: 'POST' })).json()
  const socket = new WebSocket(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
  await new Promise((resolve) => socket.once('open', resolve))
  const rtts = []
  const sent = new Map()
  socket.on('message', (data, binary) => {
    if (binary) return
    const message = JSON.parse(data.toString())
    if (message.type === 'pong' && sent.has(message.ref)) rtts.push(performance.now() - sent.get(message.ref))
  })
  socket.send(JSON.stringify({ type: 'join', room: '16-medium' }))
  const deadline = Date.now() + seconds * 1000
  for (let i = 0; Date.now() < deadline; i++) {
    sent.set(`p${i}`, performance.now())
    socket.send(JSON.stringify({ type: 'ping', ref: `p${i}` }))
    await sleep(20)
  }
  socket.close()
  return rtts
}

/** GETs `url` every 100 ms until stopped(): each probe's status and time. */
async function probeEvery (url, stopped) {
  const results = []
  while (!stopped()) {
    const started = performance.now()
    const response = await fetch(url).catch(() => null)
    await response?.arrayBuffer()
    results.push({ status: response?.status ?? 0, ms: performance.now() - started })
    await sleep(100)
  }
  return results
}

async function probes () {
  for (const pathname of ['/api/health', '/metrics']) {
    await withServer(serverEnv, async (base, port) => {
      const quiet = await pingingPlayer(base, port, 3)
      const counts = {}
      let stop = false
      const flood = Promise.all(Array.from({ length: 16 }, async () => {
        while (!stop) {
          const response = await fetch(`${base}${pathname}`).catch(() => null)
          if (!response) continue
          await response.arrayBuffer()
          counts[response.status] = (counts[response.status] ?? 0) + 1
        }
      }))
      // With a fixed MONITORING_PORT, the orchestrator's probe there every 100 ms meanwhile.
      const monitoringProbes = serverEnv.MONITORING_PORT > 0 ? probeEvery(`http://127.0.0.1:${serverEnv.MONITORING_PORT}${pathname}`, () => stop) : null
      const loud = await pingingPlayer(base, port, 10)
      stop = true
      await flood
      const total = Object.values(counts).reduce((a, b) => a + b, 0)
      console.log(`${pathname} flood, 16 clients from one address for 10 s: ${(total / 10).toFixed(0)} requests/s (${Object.entries(counts).map(([s, n]) => `${n}×${s}`).join(', ')}); ` +
        `another player's ping p50 / p99: ${percentile(quiet, 0.5).toFixed(1)} / ${percentile(quiet, 0.99).toFixed(1)} ms quiet, ${percentile(loud, 0.5).toFixed(1)} / ${percentile(loud, 0.99).toFixed(1)} ms flooded`)
      if (monitoringProbes) {
        const results = await monitoringProbes
        const ok = results.filter((r) => r.status === 200)
        console.log(`  probes on the monitoring port meanwhile: ${ok.length}/${results.length} × 200, p50 / p99 ${percentile(results.map((r) => r.ms), 0.5).toFixed(1)} / ${percentile(results.map((r) => r.ms), 0.99).toFixed(1)} ms`)
      }
    })
  }
}

const attacks = { guess, slowloris, probes }
if (!attacks[attack]) {
  console.error(`usage: node scripts/http-attacks.js ${Object.keys(attacks).join('|')} [--root DIR]`)
  process.exit(2)
}
await attacks[attack]()
