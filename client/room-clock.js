/**
 * The room's tick as the page estimates it now, for a seeds-mode room:
 * every ball is drawn at (this tick − its start tick), so this clock is
 * the page's whole notion of "now" in the room.
 *
 * Every message that names a room tick (`joined`, a batch of other
 * players' drops, a desync check) is an observation for the tick model
 * (tick-model.js: fitted to the earliest arrivals). What arrived fastest
 * was still one way old, so half the socket's round trip is added. The
 * render tick advances by the frame time, slewed towards that estimate
 * (tick-model.js advanceRenderTick): balls never jump or run backwards.
 * There is no playout buffer: nothing is interpolated between frames from
 * the server, the page's own simulation is, and a drop that arrives late
 * is fast-forwarded to where it is.
 */
import { TickModel, advanceRenderTick } from './tick-model.js'

/** Observations come only when something happens (a few a second at most): a longer window than the snapshot timeline's. */
const RATE_WINDOW_MS = 10_000
const RATE_MAX_SAMPLES = 256
const RATE_MIN_SAMPLES = 6

export class RoomClock {
  /**
   * @param {object} options
   * @param {number} options.tickRate nominal ticks per second (the server's `tickRate`)
   * @param {() => number | null} [options.rttMs] the socket's round-trip estimate (null: none yet)
   */
  constructor ({ tickRate, rttMs = () => null }) {
    this.model = new TickModel({ tickRate, windowMs: RATE_WINDOW_MS, maxSamples: RATE_MAX_SAMPLES, minSamples: RATE_MIN_SAMPLES })
    this.rttMs = rttMs
    /** @type {number | null} the tick drawn last */
    this.renderTick = null
    this.lastFrameAt = null
    this.stats = { observations: 0, snaps: 0 }
  }

  /** ticks per ms, as measured */
  get rate () { return this.model.rate }
  get jitterMs () { return this.model.jitterMs }

  /**
   * The room was at `tick` when it sent something that arrived at `now`.
   * @param {number} tick @param {number} now ms (performance.now())
   */
  observe (tick, now) {
    if (!Number.isFinite(tick) || !Number.isFinite(now)) return
    this.stats.observations++
    this.model.observe(tick, now)
  }

  /** The room's tick at `now` by the model (fractional), or null before any observation. @param {number} now ms */
  estimateAt (now) {
    const observed = this.model.tickAt(now)
    if (observed === null) return null
    return observed + ((this.rttMs() ?? 0) / 2) * this.model.rate
  }

  /**
   * Advances the render tick to frame time `now` and returns it
   * (fractional), or null before the first observation.
   * @param {number} now ms
   */
  advance (now) {
    const target = this.estimateAt(now)
    if (target === null) return null
    const elapsed = this.lastFrameAt === null ? 0 : Math.max(0, now - this.lastFrameAt)
    this.lastFrameAt = now
    this.renderTick = advanceRenderTick(this.renderTick, target, elapsed, this.model.rate, this.stats)
    return this.renderTick
  }

  /** Nothing to interpolate between in seeds mode: the shape of SnapshotTimeline.bracket(). */
  bracket () {
    return NO_SNAPSHOTS
  }

  /** How far the drawn tick is behind the estimate (ms): converging after a correction. */
  get delayMs () {
    if (this.renderTick === null || this.lastFrameAt === null) return 0
    return Math.max(0, (this.estimateAt(this.lastFrameAt) - this.renderTick) / this.model.rate)
  }
}

const NO_SNAPSHOTS = Object.freeze({ a: null, b: null })
