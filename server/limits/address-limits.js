import Redis from 'ioredis'
import { LocalAuthFailures, authFailurePolicy } from './auth-failures.js'
import { RedisAuthFailures } from './redis-auth-failures.js'
import { RedisWorkerShare, soleWorker } from './worker-share.js'
import os from 'node:os'
import { randomBytes } from 'node:crypto'

/**
 * Where the per-address HTTP limits are counted: the requests and sessions
 * per minute (@fastify/rate-limit) and the failed authentications
 * (auth-failures.js). Chosen once at start with the mode
 * (coordination/modes.js): in this process alone, or in Redis, so that a
 * cluster of N processes lets through what one would, not N times that.
 * @typedef {object} AddressLimits
 * @property {object} rateLimitOptions added to @fastify/rate-limit's options (its store)
 * @property {import('./auth-failures.js').AuthFailureLimiter} authFailures
 * @property {import('./worker-share.js').WorkerShare} workerShare how many processes divide the WebSocket budgets
 * @property {() => Promise<void>} close
 */

/** @param {import('../config.js').Config} config @returns {AddressLimits} */
export function localAddressLimits (config) {
  const authFailures = new LocalAuthFailures(authFailurePolicy(config))
  return { rateLimitOptions: {}, authFailures, workerShare: soleWorker(), close: () => authFailures.close() }
}

/**
 * Counts in Redis (REDIS_URL); the WebSocket budgets are divided by the
 * processes alive (worker-share.js says why not counted there). A request is never refused because Redis
 * is down: the rate limit lets it through (skipOnError) and failed
 * authentications are counted in this process meanwhile.
 * @param {import('../config.js').Config} config @param {import('pino').Logger} log
 * @returns {AddressLimits}
 */
export function redisAddressLimits (config, log) {
  const redis = new Redis(config.redisUrl, { maxRetriesPerRequest: 1, enableOfflineQueue: false, connectTimeout: 2000 })
  redis.on('error', (error) => log.debug({ err: error }, 'redis error (address limits)'))
  const authFailures = new RedisAuthFailures(authFailurePolicy(config), { redis, log })
  const workerShare = new RedisWorkerShare({ redis, nodeId: `${os.hostname()}-${process.pid}-${randomBytes(3).toString('hex')}`, log })
  return {
    rateLimitOptions: { redis, nameSpace: 'plinko:rate-limit:', skipOnError: true },
    authFailures,
    workerShare,
    async close () {
      await workerShare.close()
      await authFailures.close()
      await redis.quit().catch(() => redis.disconnect())
    }
  }
}
