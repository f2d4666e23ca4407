#!/usr/bin/env node
/**
 * npm run cluster -- --workers 2 [--port 8080] [--host 127.0.0.1]
 *
 * Runs N server processes on this machine behind one port, with Redis and
 * PostgreSQL: DATABASE_URL must be postgres://…; REDIS_URL is used if set,
 * otherwise a private redis-server (no persistence) is started on a free
 * loopback port and stopped on exit. Worker i listens on PORT+1+i and
 * advertises PUBLIC_URL=http://HOST:PORT/n/i; the proxy (server/cluster/proxy.js)
 * serves PORT: /n/i/… goes to worker i, everything else to the worker with
 * the fewest open connections. HTTP requests are proxied; a WebSocket is
 * handed to its worker over the IPC channel (the socket itself), so the
 * proxy carries no game frames.
 * A worker that exits is restarted after a second (its rooms move to the
 * others meanwhile, after LEASE_TTL_MS). Ctrl-C stops everything gracefully.
 */
import { spawn } from 'node:child_process'
import os from 'node:os'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { fileURLToPath } from 'node:url'
import { createProxy } from '../server/cluster/proxy.js'
import { startRedis } from '../tools/redis-process.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')
const { values } = parseArgs({
  options: {
    workers: { type: 'string', default: String(Math.max(2, Math.min(4, os.availableParallelism?.() ?? 2))) },
    port: { type: 'string', default: process.env.PORT ?? '8080' },
    host: { type: 'string', default: process.env.HOST ?? '127.0.0.1' },
    'public-host': { type: 'string' }
  }
})
const workers = Number(values.workers)
const port = Number(values.port)
if (!Number.isInteger(workers) || workers < 1 || workers > 64) fail('--workers must be an integer from 1 to 64')
if (!Number.isInteger(port) || port < 1 || port > 65535 - workers - 1) fail('--port must be a free TCP port')
if (!/^postgres(ql)?:\/\//.test(process.env.DATABASE_URL ?? '')) fail('set DATABASE_URL=postgres://user:password@host:port/database (the processes share one ledger)')
const publicHost = values['public-host'] ?? (values.host === '0.0.0.0' ? '127.0.0.1' : values.host)

let redis = null
let redisUrl = process.env.REDIS_URL
if (!redisUrl) {
  redis = await startRedis()
  redisUrl = redis.url
  console.log(`cluster: started redis-server at ${redisUrl} (set REDIS_URL to use your own)`)
}

let stopping = false
const children = []
const targets = []
for (let i = 0; i < workers; i++) {
  targets.push({ host: '127.0.0.1', port: port + 1 + i })
  startWorker(i)
}

function startWorker (i) {
  const child = spawn(process.execPath, [path.join(ROOT, 'server/server.js')], {
    cwd: ROOT,
    // The IPC channel carries the WebSockets the proxy hands over (server/cluster/socket-handoff.js).
    stdio: ['ignore', 'inherit', 'inherit', 'ipc'],
    env: { ...process.env, REDIS_URL: redisUrl, PORT: String(port + 1 + i), HOST: '127.0.0.1', PUBLIC_URL: `http://${publicHost}:${port}/n/${i}`, TRUST_PROXY: 'loopback' }
  })
  children[i] = child
  targets[i].child = child
  child.on('exit', (code, signal) => {
    if (stopping) return
    console.error(`cluster: worker ${i} exited (${signal ?? code}); restarting in 1 s`)
    setTimeout(() => { if (!stopping) startWorker(i) }, 1000).unref()
  })
}

const proxy = createProxy({ targets })
proxy.listen(port, values.host, () => console.log(`cluster: ${workers} workers behind http://${values.host}:${port} (worker i: /n/i/)`))

for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, async () => {
    if (stopping) process.exit(1)
    stopping = true
    proxy.close()
    await Promise.all(children.map((child) => new Promise((resolve) => {
      if (child.exitCode !== null || child.signalCode !== null) return resolve()
      child.once('exit', resolve)
      child.kill('SIGTERM')
    })))
    if (redis) await redis.stop()
    process.exit(0)
  })
}

function fail (message) {
  console.error(`cluster: ${message}`)
  process.exit(1)
}
