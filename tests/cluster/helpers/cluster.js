import { spawn } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import pg from 'pg'
import { freePort } from '../../../scripts/free-port.js'
import { eventually as pollUntil } from '../../helpers/eventually.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../..')
export const OPERATOR_TOKEN = 'operator-token-for-cluster-tests-0123'

// One launcher each for the whole project (npm run cluster uses them too).
export { freePort } from '../../../scripts/free-port.js'
export { startRedis } from '../../../scripts/redis-process.js'

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
      HTTP_RATE_LIMIT: '1000000',
      SESSION_RATE_LIMIT: '1000000',
      DROP_RATE_PER_IP: '1000000',
      JOIN_RATE_PER_IP: '1000000',
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

/** One query on a database URL. */
export async function query (url, sql, params = []) {
  const client = new pg.Client({ connectionString: url })
  await client.connect()
  try {
    return (await client.query(sql, params)).rows
  } finally {
    await client.end()
  }
}

/** Every player's balance equals start - bets + payouts, and no drop is left in flight. */
export async function ledgerMismatches (url, startingBalance) {
  return query(url, `SELECT p.id, p.balance,
      $1::bigint - COALESCE(SUM(d.bet), 0) + COALESCE(SUM(d.payout), 0) AS expected
    FROM players p LEFT JOIN drops d ON d.player_id = p.id
    GROUP BY p.id, p.balance
    HAVING p.balance <> $1::bigint - COALESCE(SUM(d.bet), 0) + COALESCE(SUM(d.payout), 0)`, [startingBalance])
}

/** The server tests' eventually(), polling every 50 ms: these checks query PostgreSQL. */
export function eventually (check, { timeoutMs = 30_000, intervalMs = 50 } = {}) {
  return pollUntil(check, { timeoutMs, intervalMs })
}
