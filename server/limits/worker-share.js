/**
 * How many processes share the per-address WebSocket budgets (ip-limits.js):
 * each process gives an address 1/N of the configured drops, joins, frames,
 * bytes and sockets, N the processes alive now. Why divide rather than count
 * in Redis: a drop, a join and every received frame are checked on the hot
 * path, synchronously, and a Redis round trip each (or a block reserved
 * ahead, which still needs one whenever an address's block runs out) would
 * put Redis's latency and its outages into every ball. Dividing costs one
 * Redis call per process a second. Its price: an address whose sockets all
 * land on one process gets 1/N of the configured rate there (the cluster's
 * total never exceeds the configured one).
 * @typedef {object} WorkerShare
 * @property {number} workers processes alive now (1 alone), at least 1
 * @property {(listener: (workers: number) => void) => void} onChange
 * @property {() => Promise<void>} close
 */

/** Alone: the whole budget is this process's. @returns {WorkerShare} */
export function soleWorker () {
  return { workers: 1, onChange () {}, async close () {} }
}

const WORKERS_KEY = 'plinko:address-limits:workers'

/** One heartbeat on Redis's clock (processes on other hosts may disagree on the time): the processes seen within ttl. */
const BEAT_SCRIPT = `
local t = redis.call('TIME')
local now = tonumber(t[1]) * 1000 + math.floor(tonumber(t[2]) / 1000)
local ttl = tonumber(ARGV[2])
redis.call('ZADD', KEYS[1], now, ARGV[1])
redis.call('ZREMRANGEBYSCORE', KEYS[1], '-inf', now - ttl)
redis.call('PEXPIRE', KEYS[1], ttl * 10)
return redis.call('ZCARD', KEYS[1])
`

/**
 * Each process writes its heartbeat into a sorted set every `intervalMs`
 * and counts the members seen within `ttlMs` (on Redis's clock): a killed
 * process stops counting after ttlMs. While Redis does not answer the last count stays.
 */
export class RedisWorkerShare {
  /** @param {{ redis: import('ioredis').Redis, nodeId: string, ttlMs?: number, intervalMs?: number, log: import('pino').Logger }} options */
  constructor ({ redis, nodeId, ttlMs = 3000, intervalMs = 1000, log }) {
    this.redis = redis
    this.nodeId = nodeId
    this.ttlMs = ttlMs
    this.log = log
    this.workers = 1
    redis.defineCommand('plinkoWorkerBeat', { numberOfKeys: 1, lua: BEAT_SCRIPT })
    /** @type {((workers: number) => void)[]} */
    this.listeners = []
    // The connection is not up yet (no offline queue): the first beat waits for it.
    if (redis.status === 'ready') this.beat()
    else redis.once('ready', () => this.beat())
    this.timer = setInterval(() => this.beat(), intervalMs).unref()
  }

  /** @param {(workers: number) => void} listener */
  onChange (listener) {
    this.listeners.push(listener)
  }

  async beat () {
    try {
      const count = Number(await this.redis.plinkoWorkerBeat(WORKERS_KEY, this.nodeId, this.ttlMs))
      this._set(Math.max(1, count))
    } catch (error) {
      this.log.debug({ err: error }, 'worker heartbeat failed (address limits keep the last share)')
    }
  }

  /** @param {number} workers */
  _set (workers) {
    if (workers === this.workers) return
    this.workers = workers
    for (const listener of this.listeners) listener(workers)
  }

  async close () {
    clearInterval(this.timer)
    await this.redis.zrem(WORKERS_KEY, this.nodeId).catch(() => {})
  }
}
