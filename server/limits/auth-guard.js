import { gameError } from '../errors.js'

/**
 * The per-address throttle in front of every token check (operator and
 * player; HTTP and WebSocket), over an AuthFailureLimiter
 * (auth-failures.js). Operator and player failures are counted apart, so a
 * player-token spray from an address does not lock its operator out, nor
 * the reverse.
 */
export class AuthGuard {
  /**
   * @param {{ limiter: import('./auth-failures.js').AuthFailureLimiter, metrics: import('../metrics.js').Metrics, log: import('pino').Logger }} options
   */
  constructor ({ limiter, metrics, log }) {
    this.limiter = limiter
    this.metrics = metrics
    this.log = log
  }

  /**
   * Throws 429 E_RATE_LIMITED (and sets Retry-After on `reply`) while the
   * address is blocked: the token is then not looked at.
   * @param {'operator' | 'player'} kind @param {string} ip @param {import('fastify').FastifyReply} [reply]
   */
  async admit (kind, ip, reply) {
    const block = await this.blocked(kind, ip)
    if (!block) return
    reply?.header('retry-after', String(block.retryAfter))
    throw gameError('E_RATE_LIMITED', block.message)
  }

  /**
   * The address's block, or null: whole seconds left of it and what the
   * request is told; a blocked request is counted as throttled. For a
   * caller that answers the block itself (the operator token check,
   * routes/audit-token-check.js).
   * @param {'operator' | 'player'} kind @param {string} ip
   * @returns {Promise<{ retryAfter: number, message: string } | null>}
   */
  async blocked (kind, ip) {
    const waitMs = await this.limiter.blockedFor(`${kind}:${ip}`)
    if (waitMs <= 0) return null
    this.metrics.authThrottled.labels(kind).inc()
    const retryAfter = Math.ceil(waitMs / 1000)
    return { retryAfter, message: `too many wrong ${kind} tokens from this address; retry in ${retryAfter} s` }
  }

  /** A wrong token from `ip`. @param {'operator' | 'player'} kind @param {string} ip */
  async failed (kind, ip) {
    this.metrics.authFailures.labels(kind).inc()
    const blockMs = await this.limiter.fail(`${kind}:${ip}`)
    if (blockMs > 0) this.log.warn({ kind, remoteAddress: ip, blockMs }, `too many wrong ${kind} tokens; address blocked for ${Math.ceil(blockMs / 1000)} s`)
  }
}

