import { spawn } from 'node:child_process'
import path from 'node:path'
import { beforeAll, afterAll } from 'vitest'
import { fileURLToPath } from 'node:url'
import { freePort } from '../../../tools/free-port.js'
import { eventually as pollUntil } from '../../../tools/eventually.js'
import { LIFTED_LIMITS } from '../../../tools/lifted-limits.js'
import { GameClient } from '../../server/helpers/game-client.js'
import { startPostgres } from '../../../tools/postgres-process.js'
import { startRedis as startRedisProcess } from '../../../tools/redis-process.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../..')
export const OPERATOR_TOKEN = 'operator-token-for-cluster-tests-0123'

/**
 * Players' sockets on cluster members, closed together at the end of a test
 * file: `connect(node, token)` opens one on `node` (anything with
 * `wsUrl(token)`), `join(client, room)` joins and resolves with the reply
 * to that join (`joined`, or an error such as E_WRONG_NODE).
 */
export function playerSockets () {
  const clients = []
  return {
    async connect (node, token) {
      const client = await GameClient.connect(node.wsUrl(token))
      clients.push(client)
      return client
    },
    async join (client, room) {
      const ref = `join-${room}-${Math.random()}`
      client.send({ type: 'join', room, ref })
      return client.take((m) => m.ref === ref)
    },
    async closeAll () {
      for (const client of clients.splice(0)) await client.close().catch(() => {})
    }
  }
}

/**
 * What a cluster test file runs on, started before its tests and stopped
 * after them (nodes and player sockets first): a throwaway PostgreSQL and
 * Redis, the nodes it starts with `startNode`, the sockets of
 * playerSockets(). Use inside a describe().
 */
export function clusterTestbed () {
  const testbed = {
    /** @type {any} */ postgres: null,
    /** @type {any} */ redis: null,
    nodes: [],
    ...playerSockets(),
    /** A cluster member on `databaseUrl` and the testbed's Redis, stopped with the testbed. @param {{ databaseUrl: string, env?: Record<string, string> }} options */
    async startNode ({ databaseUrl, env }) {
      const node = await startNode({ databaseUrl, redisUrl: testbed.redis.url, env })
      testbed.nodes.push(node)
      return node
    }
  }
  beforeAll(async () => {
    testbed.postgres = await startPostgres()
    testbed.redis = await startRedisProcess()
  })
  afterAll(async () => {
    await testbed.closeAll()
    for (const node of testbed.nodes) await node.stop().catch(() => {})
    await testbed.redis?.stop()
    await testbed.postgres?.stop()
  })
  return testbed
}

// One launcher each for the whole project (npm run cluster uses them too).
export { freePort } from '../../../tools/free-port.js'
export { startRedis } from '../../../tools/redis-process.js'
export { query, ledgerMismatches, roomTotalMismatches } from '../../../tools/ledger-checks.js'

/**
 * `node server/server.js` as a cluster member on a free port, its PUBLIC_URL
 * set to that port. Resolves once it listens.
 * @param {{ databaseUrl: string, redisUrl: string, env?: Record<string, string> }} options
 */
export async function startNode ({ databaseUrl, redisUrl, env = {} }) {
  const port = await freePort()
  const url = `http://127.0.0.1:${port}`
  const child = spawn(process.execPath, [path.join(ROOT, 'server/server.js')], {
    cwd: ROOT,
    env: {
      ...process.env,
      DATABASE_URL: databaseUrl,
      REDIS_URL: redisUrl,
      PUBLIC_URL: url,
      PORT: String(port),
      HOST: '127.0.0.1',
      LOG_LEVEL: 'warn',
      OPERATOR_TOKEN,
      CLIENT_DIR: '/nonexistent/plinko-client',
      ...LIFTED_LIMITS,
      ...env
    },
    stdio: ['ignore', 'pipe', 'pipe']
  })
  let output = ''
  child.stdout.on('data', (chunk) => { output += chunk })
  child.stderr.on('data', (chunk) => { output += chunk })
  const exited = new Promise((resolve) => child.once('exit', (code, signal) => resolve({ code, signal })))
  const node = {
    child,
    port,
    url,
    exited,
    get output () { return output },
    wsUrl: (token) => `ws://127.0.0.1:${port}/ws?token=${token}`,
    async api (method, pathname, body) {
      const response = await fetch(url + pathname, { method, headers: body ? { 'content-type': 'application/json' } : {}, body: body ? JSON.stringify(body) : undefined })
      return { status: response.status, body: await response.json().catch(() => null) }
    },
    async session () {
      const { status, body } = await node.api('POST', '/api/session')
      if (status !== 201) throw new Error(`session: ${status}`)
      return body
    },
    kill (signal = 'SIGKILL') { child.kill(signal); return exited },
    async stop () {
      if (child.exitCode !== null || child.signalCode !== null) return exited
      child.kill('SIGTERM')
      return exited
    }
  }
  // Ready when /api/health answers.
  const deadline = Date.now() + 30_000
  for (;;) {
    if (child.exitCode !== null) throw new Error(`server exited before listening:\n${output}`)
    try {
      const response = await fetch(url + '/api/rooms')
      if (response.ok) break
    } catch {}
    if (Date.now() > deadline) { child.kill('SIGKILL'); throw new Error(`server did not start:\n${output}`) }
    await new Promise((resolve) => setTimeout(resolve, 50))
  }
  return node
}

/** The server tests' eventually(), polling every 50 ms: these checks query PostgreSQL. */
export function eventually (check, { timeoutMs = 30_000, intervalMs = 50 } = {}) {
  return pollUntil(check, { timeoutMs, intervalMs })
}
