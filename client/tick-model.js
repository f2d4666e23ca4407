/**
 * A model of a room's clock as seen from the page: tick ≈ offset + now · rate,
 * fitted to the *earliest* arrivals of the ticks the server names (network
 * delay only ever makes a message later; a late bias fades slowly), with
 * the rate fitted by least squares over a recent window (tests run servers
 * faster than 60 Hz). Both render clocks use it: the snapshot timeline
 * (which renders a playout delay behind it) and the seeds-mode room clock
 * (which renders at it).
 */

/** The model forgets a late bias at this rate per observation. */
const OFFSET_DECAY = 0.02
const JITTER_GAIN = 0.1
const RATE_MIN_SPAN_MS = 1000
/** The render clock may run this much faster or slower than real time while converging. */
const MAX_SLEW = 0.1

export class TickModel {
  /**
   * @param {object} options
   * @param {number} options.tickRate nominal ticks per second
   * @param {number} options.windowMs observations of this last stretch estimate the rate
   * @param {number} options.maxSamples at most this many of them
   * @param {number} options.minSamples fewer than this: the nominal rate
   */
  constructor ({ tickRate, windowMs, maxSamples, minSamples }) {
    this.nominalRate = tickRate / 1000
    this.windowMs = windowMs
    this.maxSamples = maxSamples
    this.minSamples = minSamples
    this.reset()
  }

  reset () {
    /** ticks per ms */
    this.rate = this.nominalRate
    /** @type {number | null} */
    this.offset = null
    /** mean lateness of observations behind the earliest-arrival fit (ms) */
    this.jitterMs = 0
    this._samples = []
  }

  /**
   * The server was at `tick` when it sent something that arrived at `now`.
   * @param {number} tick @param {number} now ms (performance.now())
   */
  observe (tick, now) {
    const samples = this._samples
    samples.push(now, tick)
    let old = 0
    while (old < samples.length - 2 && (now - samples[old] > this.windowMs || samples.length - old > 2 * this.maxSamples)) old += 2
    if (old > 0) samples.splice(0, old)
    this._estimateRate()
    const sample = tick - now * this.rate
    if (this.offset === null || sample > this.offset) {
      this.offset = sample
      return
    }
    const latenessMs = (this.offset - sample) / this.rate
    this.jitterMs += (latenessMs - this.jitterMs) * JITTER_GAIN
    this.offset += (sample - this.offset) * OFFSET_DECAY
  }

  /** The tick the model expects at `now` (as of arrival: one way behind the server), or null. @param {number} now */
  tickAt (now) {
    return this.offset === null ? null : this.offset + now * this.rate
  }

  _estimateRate () {
    const samples = this._samples
    const n = samples.length / 2
    if (n < this.minSamples || samples[samples.length - 2] - samples[0] < RATE_MIN_SPAN_MS) return
    // Least squares slope of tick over time.
    let meanT = 0; let meanK = 0
    for (let i = 0; i < samples.length; i += 2) { meanT += samples[i]; meanK += samples[i + 1] }
    meanT /= n; meanK /= n
    let num = 0; let den = 0
    for (let i = 0; i < samples.length; i += 2) {
      const dt = samples[i] - meanT
      num += dt * (samples[i + 1] - meanK)
      den += dt * dt
    }
    if (den <= 0) return
    const nominal = this.nominalRate
    const slope = Math.min(nominal * 8, Math.max(nominal / 8, num / den))
    if (this.offset !== null) {
      // Keep the model continuous at the last sample when the rate changes.
      const lastT = samples[samples.length - 2]
      this.offset += (this.rate - slope) * lastT
    }
    this.rate = slope
  }
}

/** Further than this from its target, a render clock snaps instead of slewing. */
const SNAP_MS = 750

/**
 * The next render tick: `current` advanced by `elapsedMs` at `rate` and
 * slewed towards `target` by at most ±10 % of that step, so it never jumps
 * or runs backwards. Further than SNAP_MS off (a hidden tab, a stall) it
 * snaps to the target, still never backwards, and counts it in
 * `stats.snaps`; null `current` starts at `target`.
 * @param {number | null} current @param {number} target @param {number} elapsedMs @param {number} rate ticks per ms
 * @param {{ snaps: number }} stats
 */
export function advanceRenderTick (current, target, elapsedMs, rate, stats) {
  if (current === null) return target
  if (Math.abs(target - current) > SNAP_MS * rate) {
    stats.snaps++
    return Math.max(current, target)
  }
  const step = elapsedMs * rate
  const error = target - (current + step)
  const limit = MAX_SLEW * step
  return current + step + Math.max(-limit, Math.min(limit, error))
}
