/**
 * How failed authentications are throttled per client address (issue #21):
 * `limit` wrong tokens per `windowMs`, then the address is blocked for
 * `blockMs`; each further block in a row lasts twice as long, up to
 * `maxBlockMs`; an address that stays out of blocks for `maxBlockMs` starts
 * again from `blockMs`. While blocked, every authenticating request from
 * the address is refused with 429 before its token is looked at, so a
 * right guess is no different from a wrong one; a success never resets
 * the count (a shared address's honest users would reset it for an
 * attacker among them).
 *
 * Two implementations behind one interface, chosen once at start
 * (address-limits.js): LocalAuthFailures (one process) and
 * RedisAuthFailures (a cluster: the same counts for every process).
 *
 * @typedef {object} AuthFailurePolicy
 * @property {number} limit failures allowed per window
 * @property {number} windowMs
 * @property {number} blockMs the first block
 * @property {number} maxBlockMs the longest block, and how long an address must stay out of blocks to start over
 *
 * @typedef {object} AuthFailureLimiter
 * @property {(key: string) => Promise<number>} blockedFor ms left of the key's block, 0 if none
 * @property {(key: string) => Promise<number>} fail counts a failure; returns the block it started (ms), or 0
 * @property {() => Promise<void>} close
 */

/** Defaults beside AUTH_FAILURE_LIMIT and AUTH_BLOCK_MS: counted per minute, blocks up to an hour. */
export const AUTH_WINDOW_MS = 60_000
export const AUTH_MAX_BLOCK_MS = 3_600_000

/** @param {import('../config.js').Config} config @returns {AuthFailurePolicy} */
export function authFailurePolicy (config) {
  return { limit: config.authFailureLimit, windowMs: AUTH_WINDOW_MS, blockMs: config.authBlockMs, maxBlockMs: Math.max(config.authBlockMs, AUTH_MAX_BLOCK_MS) }
}

/**
 * One step of the policy on one address's state (the Redis script does the
 * same in Lua): returns the block started, or 0. Mutates `state`.
 * @param {{ count: number, windowStart: number, blockedUntil: number, strikes: number }} state
 * @param {AuthFailurePolicy} policy @param {number} now
 */
export function countFailure (state, policy, now) {
  if (state.blockedUntil > now) return 0
  if (now - state.windowStart >= policy.windowMs) {
    state.windowStart = now
    state.count = 0
  }
  if (state.blockedUntil > 0 && now - state.blockedUntil >= policy.maxBlockMs) state.strikes = 0
  state.count++
  if (state.count < policy.limit) return 0
  state.strikes++
  const block = Math.min(policy.blockMs * 2 ** Math.min(state.strikes - 1, 30), policy.maxBlockMs)
  state.blockedUntil = now + block
  state.count = 0
  state.windowStart = state.blockedUntil
  return block
}

/** @implements {AuthFailureLimiter} */
export class LocalAuthFailures {
  /** @param {AuthFailurePolicy} policy @param {{ now?: () => number }} [options] */
  constructor (policy, { now = Date.now } = {}) {
    this.policy = policy
    this.now = now
    /** @type {Map<string, { count: number, windowStart: number, blockedUntil: number, strikes: number }>} */
    this.entries = new Map()
    // Addresses past every window and block are forgotten, so a spray of addresses cannot grow the map for ever.
    this.sweeper = setInterval(() => this.sweep(), policy.windowMs).unref()
  }

  async blockedFor (key) {
    const entry = this.entries.get(key)
    return entry ? Math.max(0, entry.blockedUntil - this.now()) : 0
  }

  async fail (key) {
    let entry = this.entries.get(key)
    if (!entry) this.entries.set(key, (entry = { count: 0, windowStart: this.now(), blockedUntil: 0, strikes: 0 }))
    return countFailure(entry, this.policy, this.now())
  }

  sweep () {
    const now = this.now()
    for (const [key, entry] of this.entries) {
      if (now - entry.windowStart >= this.policy.windowMs && now - entry.blockedUntil >= this.policy.maxBlockMs) this.entries.delete(key)
    }
  }

  async close () { clearInterval(this.sweeper) }
}
