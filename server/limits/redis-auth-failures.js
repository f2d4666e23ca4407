import { LocalAuthFailures } from './auth-failures.js'

/** countFailure() of auth-failures.js in Lua, on Redis's clock; the key expires once nothing in it matters. */
const FAIL_SCRIPT = `
local limit, windowMs, blockMs, maxBlockMs = tonumber(ARGV[1]), tonumber(ARGV[2]), tonumber(ARGV[3]), tonumber(ARGV[4])
local t = redis.call('TIME')
local now = tonumber(t[1]) * 1000 + math.floor(tonumber(t[2]) / 1000)
local s = redis.call('HMGET', KEYS[1], 'count', 'windowStart', 'blockedUntil', 'strikes')
local count, windowStart, blockedUntil, strikes = tonumber(s[1]) or 0, tonumber(s[2]) or now, tonumber(s[3]) or 0, tonumber(s[4]) or 0
if blockedUntil > now then return 0 end
if now - windowStart >= windowMs then windowStart = now; count = 0 end
if blockedUntil > 0 and now - blockedUntil >= maxBlockMs then strikes = 0 end
count = count + 1
local block = 0
if count >= limit then
  strikes = strikes + 1
  block = math.min(blockMs * 2 ^ math.min(strikes - 1, 30), maxBlockMs)
  blockedUntil = now + block
  count = 0
  windowStart = blockedUntil
end
redis.call('HSET', KEYS[1], 'count', count, 'windowStart', windowStart, 'blockedUntil', blockedUntil, 'strikes', strikes)
redis.call('PEXPIRE', KEYS[1], math.max(windowStart - now, 0) + windowMs + maxBlockMs)
return block
`

const BLOCKED_SCRIPT = `
local t = redis.call('TIME')
local now = tonumber(t[1]) * 1000 + math.floor(tonumber(t[2]) / 1000)
local blockedUntil = tonumber(redis.call('HGET', KEYS[1], 'blockedUntil')) or 0
return math.max(blockedUntil - now, 0)
`

/**
 * Failed authentications counted in Redis, so a cluster's processes share
 * one budget per address (auth-failures.js). While Redis does not answer,
 * each process counts on its own (LocalAuthFailures): the throttle never
 * turns off, and honest users are not refused for Redis's fault.
 * @implements {import('./auth-failures.js').AuthFailureLimiter}
 */
export class RedisAuthFailures {
  /**
   * @param {import('./auth-failures.js').AuthFailurePolicy} policy
   * @param {{ redis: import('ioredis').Redis, log: import('pino').Logger, prefix?: string }} options
   */
  constructor (policy, { redis, log, prefix = 'plinko:auth-failures:' }) {
    this.policy = policy
    this.redis = redis
    this.log = log
    this.prefix = prefix
    this.fallback = new LocalAuthFailures(policy)
    /** Warned of this outage already (once per outage, not per request). */
    this.degraded = false
    redis.defineCommand('plinkoAuthFail', { numberOfKeys: 1, lua: FAIL_SCRIPT })
    redis.defineCommand('plinkoAuthBlocked', { numberOfKeys: 1, lua: BLOCKED_SCRIPT })
  }

  async blockedFor (key) {
    try {
      const blocked = Number(await this.redis.plinkoAuthBlocked(this.prefix + key))
      this._redisAnswered()
      return Math.max(blocked, await this.fallback.blockedFor(key))
    } catch (error) {
      this._redisFailed(error)
      return this.fallback.blockedFor(key)
    }
  }

  async fail (key) {
    const { limit, windowMs, blockMs, maxBlockMs } = this.policy
    try {
      const block = Number(await this.redis.plinkoAuthFail(this.prefix + key, limit, windowMs, blockMs, maxBlockMs))
      this._redisAnswered()
      return block
    } catch (error) {
      this._redisFailed(error)
      return this.fallback.fail(key)
    }
  }

  _redisFailed (error) {
    if (this.degraded) return
    this.degraded = true
    this.log.warn({ err: error }, 'failed authentications: redis does not answer; counting them in this process until it does')
  }

  _redisAnswered () {
    if (!this.degraded) return
    this.degraded = false
    this.log.info('failed authentications: counted in redis again')
  }

  async close () { await this.fallback.close() }
}
