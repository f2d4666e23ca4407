import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import Redis from 'ioredis'
import pino from 'pino'
import { startRedis } from '../../tools/redis-process.js'
import { eventually } from '../../tools/eventually.js'
import { RedisWorkerShare } from '../../server/limits/worker-share.js'

/**
 * How many processes divide the per-address WebSocket budgets
 * (server/limits/worker-share.js), on a real Redis: each heartbeat counts,
 * a closed process leaves at once, one that stops beating (killed) after
 * the TTL.
 */
describe('RedisWorkerShare', () => {
  let redisProcess
  const clients = []
  beforeAll(async () => { redisProcess = await startRedis() })
  afterAll(async () => {
    for (const client of clients) client.disconnect()
    await redisProcess?.stop()
  })

  function share (nodeId) {
    const redis = new Redis(redisProcess.url)
    clients.push(redis)
    return new RedisWorkerShare({ redis, nodeId, ttlMs: 400, intervalMs: 50, log: pino({ level: 'silent' }) })
  }

  it('counts the processes beating, forgets one that closes at once and one that stops beating after the TTL', async () => {
    const a = share('a')
    const seen = []
    a.onChange((workers) => seen.push(workers))
    const b = share('b')
    const c = share('c')
    await eventually(() => a.workers === 3 && b.workers === 3 && c.workers === 3)
    await c.close()
    await eventually(() => a.workers === 2)
    clearInterval(b.timer) // as if killed: no goodbye
    await eventually(() => a.workers === 1)
    expect(seen.at(-1)).toBe(1)
    expect(seen).toContain(3)
    await a.close()
  })
})
