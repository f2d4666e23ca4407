/**
 * Leases in Redis: a key holds its owner's id and expires after a TTL unless
 * the owner renews it. Taking is SET NX PX; renewing and releasing are Lua
 * scripts that compare the owner first, so a process can never extend or
 * delete a lease that has already passed to another one.
 */

/** KEYS[1] lease, ARGV[1] owner, ARGV[2] ttl ms → 1 held (taken, or already ours), 0 someone else's. */
const TAKE = `
if redis.call('SET', KEYS[1], ARGV[1], 'NX', 'PX', ARGV[2]) then return 1 end
if redis.call('GET', KEYS[1]) == ARGV[1] then redis.call('PEXPIRE', KEYS[1], ARGV[2]) return 1 end
return 0`

/**
 * Renews each lease in KEYS that is still ours; one that expired without
 * anyone taking it is taken back. Returns 1/0 per key (0: lost to another owner).
 */
const RENEW = `
local held = {}
for i, key in ipairs(KEYS) do
  local owner = redis.call('GET', key)
  if owner == ARGV[1] then redis.call('PEXPIRE', key, ARGV[2]) held[i] = 1
  elseif owner == false then redis.call('SET', key, ARGV[1], 'PX', ARGV[2]) held[i] = 1
  else held[i] = 0 end
end
return held`

/** Deletes the lease only if it is still ours. */
const RELEASE = `
if redis.call('GET', KEYS[1]) == ARGV[1] then return redis.call('DEL', KEYS[1]) end
return 0`

/**
 * @param {import('ioredis').Redis} redis
 */
export function defineLeaseCommands (redis) {
  if (typeof redis.leaseTake === 'function') return
  redis.defineCommand('leaseTake', { numberOfKeys: 1, lua: TAKE })
  redis.defineCommand('leaseRelease', { numberOfKeys: 1, lua: RELEASE })
  // Variable key count: the caller passes it first.
  redis.defineCommand('leaseRenew', { lua: RENEW })
}

/** A set of leases held by one owner, renewed together. */
export class Leases {
  /**
   * @param {{ redis: import('ioredis').Redis, owner: string, ttlMs: number }} options
   */
  constructor ({ redis, owner, ttlMs }) {
    defineLeaseCommands(redis)
    this.redis = redis
    this.owner = owner
    this.ttlMs = ttlMs
  }

  /** @param {string} key @returns {Promise<boolean>} true if we hold it now */
  async take (key) {
    return (await this.redis.leaseTake(key, this.owner, this.ttlMs)) === 1
  }

  /** @param {string[]} keys @returns {Promise<string[]>} the keys lost to another owner */
  async renew (keys) {
    if (keys.length === 0) return []
    const held = await this.redis.leaseRenew(keys.length, ...keys, this.owner, this.ttlMs)
    return keys.filter((_, i) => held[i] !== 1)
  }

  /** @param {string} key @returns {Promise<boolean>} true if it was ours */
  async release (key) {
    return (await this.redis.leaseRelease(key, this.owner)) === 1
  }
}
