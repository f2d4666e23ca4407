import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import Redis from 'ioredis'
import pino from 'pino'
import { startRedis } from '../../tools/redis-process.js'
import { eventually } from '../../tools/eventually.js'
import { RedisAuthFailures } from '../../server/limits/redis-auth-failures.js'

/**
 * Issue #21 (d): the Redis script's blocks (server/limits/redis-auth-failures.js)
 * on a real Redis and its clock: each block in a row lasts twice the last, up
 * to the longest, shared by every process on the same Redis, and an address
 * a longest block out of blocks starts over.
 */
describe('RedisAuthFailures: blocks in a row double, across processes, up to the longest', () => {
  let redisProcess, redisA, redisB
  beforeAll(async () => {
    redisProcess = await startRedis()
    redisA = new Redis(redisProcess.url)
    redisB = new Redis(redisProcess.url)
  })
  afterAll(async () => {
    await redisA?.quit()
    await redisB?.quit()
    await redisProcess?.stop()
  })

  it('blocks for 100, 200, 400, then 700 ms (the longest), alternating two processes; 100 again once 700 ms passed without a block', async () => {
    const policy = { limit: 2, windowMs: 60_000, blockMs: 100, maxBlockMs: 700 }
    const log = pino({ level: 'silent' })
    const processes = [new RedisAuthFailures(policy, { redis: redisA, log }), new RedisAuthFailures(policy, { redis: redisB, log })]
    const key = `player:10.0.0.${Math.floor(Math.random() * 250)}`
    const blocks = []
    for (let i = 0; i < 4; i++) {
      const limiter = processes[i % 2]
      expect(await limiter.fail(key)).toBe(0)
      blocks.push(await processes[(i + 1) % 2].fail(key))
      // Shared: the other process waits it out.
      await eventually(async () => (await limiter.blockedFor(key)) === 0, { intervalMs: 5 })
    }
    expect(blocks).toEqual([100, 200, 400, 700])
    // An address a longest block (700 ms) out of blocks starts over at the first block.
    const freeSince = Date.now()
    await eventually(() => Date.now() - freeSince > 750, { intervalMs: 20 })
    expect(await processes[0].fail(key)).toBe(0)
    expect(await processes[1].fail(key)).toBe(100)
    for (const limiter of processes) await limiter.close()
  })
})
