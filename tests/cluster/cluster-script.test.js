import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { spawn } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { startPostgres } from '../../tools/postgres-process.js'
import { GameClient } from '../server/helpers/game-client.js'
import { startRedis, eventually, OPERATOR_TOKEN } from './helpers/cluster.js'
import { freePortRun } from '../../tools/free-port.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')

describe('npm run cluster -- --workers 2', () => {
  let postgres, redis
  beforeAll(async () => { postgres = await startPostgres(); redis = await startRedis() })
  afterAll(async () => { await redis?.stop(); await postgres?.stop() })

  it('serves two workers behind one port, routes /n/i/ to worker i and follows E_WRONG_NODE through the proxy', async () => {
    const port = await freePortRun(3)
    const databaseUrl = await postgres.createDatabase()
    const child = spawn(process.execPath, [path.join(ROOT, 'scripts/cluster.js'), '--workers', '2', '--port', String(port)], {
      cwd: ROOT,
      env: { ...process.env, DATABASE_URL: databaseUrl, REDIS_URL: redis.url, LOG_LEVEL: 'warn', OPERATOR_TOKEN, CLIENT_DIR: '/nonexistent/plinko-client', LEASE_TTL_MS: '1500' },
      stdio: ['ignore', 'pipe', 'pipe']
    })
    let output = ''
    child.stdout.on('data', (c) => { output += c })
    child.stderr.on('data', (c) => { output += c })
    const exited = new Promise((resolve) => child.once('exit', (code) => resolve(code)))
    const base = `http://127.0.0.1:${port}`
    const clients = []
    try {
      for (const i of [0, 1]) await eventually(async () => (await fetch(`${base}/n/${i}/api/health`).catch(() => null))?.ok, { timeoutMs: 20_000 })
      const session = await (await fetch(`${base}/api/session`, { method: 'POST' })).json()
      // Worker 0 runs 10-low; a client reaching worker 1 is sent to worker 0's URL on the same port.
      const on0 = await GameClient.connect(`ws://127.0.0.1:${port}/n/0/ws?token=${session.token}`)
      clients.push(on0)
      on0.send({ type: 'join', room: '10-low', ref: 1 })
      expect(await on0.take((m) => m.ref === 1)).toMatchObject({ type: 'joined' })
      const on1 = await GameClient.connect(`ws://127.0.0.1:${port}/n/1/ws?token=${session.token}`)
      clients.push(on1)
      on1.send({ type: 'join', room: '10-low', ref: 2 })
      const moved = await on1.take((m) => m.ref === 2)
      expect(moved).toMatchObject({ type: 'error', code: 'E_WRONG_NODE', owner: `${base}/n/0` })
      const followed = await GameClient.connect(`${moved.owner.replace(/^http/, 'ws')}/ws?token=${session.token}`)
      clients.push(followed)
      followed.send({ type: 'join', room: '10-low', ref: 3 })
      expect(await followed.take((m) => m.ref === 3)).toMatchObject({ type: 'joined' })
      followed.send({ type: 'drop', bet: 5, ref: 4 })
      const dropped = await followed.take((m) => m.ref === 4)
      expect(dropped.type).toBe('dropped')
      await followed.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
      const { rooms } = await (await fetch(`${base}/api/rooms`)).json()
      expect(rooms.find((r) => r.id === '10-low')).toMatchObject({ owner: `${base}/n/0`, players: 2 })
    } finally {
      for (const client of clients) await client.close().catch(() => {})
      child.kill('SIGTERM')
    }
    expect(await exited, output).toBe(0)
  })
})
