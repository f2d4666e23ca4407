/**
 * A token bucket: `burst` tokens, refilled at `rate` per second. Used to
 * limit drops and joins per player and per IP; time comes from a
 * monotonic clock.
 */
export class TokenBucket {
  /** @param {{ rate: number, burst: number, now?: () => number }} options now() in ms */
  constructor ({ rate, burst, now = () => performance.now() }) {
    this.rate = rate
    this.burst = burst
    this.now = now
    this.tokens = burst
    this.updatedAt = now()
  }

  /** Takes `count` tokens (one by default) if there are that many. @returns {boolean} */
  take (count = 1) {
    this._refill()
    if (this.tokens < count) return false
    this.tokens -= count
    return true
  }

  /** Whether the bucket has refilled to its burst (nothing to remember). */
  isFull () {
    this._refill()
    return this.tokens >= this.burst
  }

  /** A new rate and burst from now on: what has accrued so far counts at the old rate, capped at the new burst. */
  resize (rate, burst) {
    this._refill()
    this.rate = rate
    this.burst = burst
    this.tokens = Math.min(this.tokens, burst)
  }

  _refill () {
    const now = this.now()
    this.tokens = Math.min(this.burst, this.tokens + (now - this.updatedAt) * this.rate / 1000)
    this.updatedAt = now
  }
}
