/**
 * The room's tick as the page estimates it, for a seeds-mode room: every
 * ball is drawn at (render tick − its start tick), so this clock is the
 * page's whole notion of "now" in the room.
 *
 * Every message that names a room tick (`joined`, a drop-events frame:
 * a batch of other players' drops or a desync check alone, and the `pong`
 * of every heartbeat, seeds-delivery.js applyPong) is an
 * observation for the tick model (tick-model.js: fitted to the earliest
 * arrivals, which were still one way old): the room's tick now is the
 * model's plus half the socket's round trip.
 *
 * The page draws the room a little behind that: one way plus
 * SETTLE_MARGIN_MS. A message the server sends as something happens then
 * reaches the page before the page draws it happening, whatever the
 * link: the player's own ball starts at the top of the board (its
 * `dropped` comes after the drop's commit). Its `settled` rides in the
 * room's next drop-events frame (up to 1/EVENT_HZ after the payout's
 * commit), so the result is revealed as the ball lands or shortly after
 * (drop-results.js waits for it). Other players' drops,
 * batched up to 1/EVENT_HZ, may still arrive after their start: they are
 * fast-forwarded. The render tick advances by the frame time, slewed
 * towards its target (tick-model.js advanceRenderTick): balls never jump
 * or run backwards.
 */
import { TickModel, advanceRenderTick } from './tick-model.js'

/** Observations come only when something happens (a few a second at most): a longer window than the snapshot timeline's. */
const RATE_WINDOW_MS = 10_000
const RATE_MAX_SAMPLES = 256
const RATE_MIN_SAMPLES = 6
/** Covers the server's commit of a drop or a payout before it announces it (a ledger batch). */
export const SETTLE_MARGIN_MS = 100

export class RoomClock {
  /**
   * @param {object} options
   * @param {number} options.tickRate nominal ticks per second (the server's `tickRate`)
   * @param {() => number | null} [options.rttMs] the socket's round-trip estimate (null: none yet)
   */
  constructor ({ tickRate, rttMs = () => null }) {
    this.model = new TickModel({ tickRate, windowMs: RATE_WINDOW_MS, maxSamples: RATE_MAX_SAMPLES, minSamples: RATE_MIN_SAMPLES })
    this.rttMs = rttMs
    this.stats = { observations: 0, snaps: 0 }
    this.follower = new RenderTickFollower(this.stats)
    /** Called after each observation (the line may have moved). @type {() => void} */
    this.onChange = () => {}
  }

  /** the tick drawn last */
  get renderTick () { return this.follower.renderTick }

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
    this.onChange()
  }

  /** The room's tick at `now` by the model (fractional), or null before any observation. @param {number} now ms */
  estimateAt (now) {
    const observed = this.model.tickAt(now)
    if (observed === null) return null
    return observed + ((this.rttMs() ?? 0) / 2) * this.model.rate
  }

  /** How far behind the room's tick the page draws (ms): one way, and the commit margin. */
  get delayMs () {
    return (this.rttMs() ?? 0) / 2 + SETTLE_MARGIN_MS
  }

  /**
   * Advances the render tick to frame time `now` and returns it
   * (fractional), or null before the first observation.
   * @param {number} now ms
   */
  advance (now) {
    // The model has the line's shape (offset, rate): no object a frame.
    return this.follower.advance(this.model.offset === null ? null : this.model, now)
  }

  /**
   * Where the render tick is headed, as a line in page time (null before
   * the first observation): what a room drawn elsewhere (the board worker,
   * board-worker-room.js) needs to run the same clock; it changes only when
   * the clock observes a tick (onChange).
   * @returns {ClockLine | null}
   */
  get line () {
    return this.model.offset === null ? null : { offset: this.model.offset, rate: this.model.rate }
  }

  /** Nothing to interpolate between in seeds mode: the shape of SnapshotTimeline.bracket(). */
  bracket () {
    return NO_SNAPSHOTS
  }
}

const NO_SNAPSHOTS = Object.freeze({ a: null, b: null })

/**
 * The room's tick by the clock's model: tick ≈ offset + now · rate (page time, ms).
 * @typedef {{ offset: number, rate: number }} ClockLine
 */

/**
 * The render tick at page time `now`: the model's tick SETTLE_MARGIN_MS
 * ago. The room's tick now is the model's (as of arrival) plus half the
 * round trip, and the page draws one way plus the margin behind the room:
 * the round trip cancels out.
 * @param {ClockLine} line @param {number} now ms
 */
export function renderTarget (line, now) {
  return line.offset + (now - SETTLE_MARGIN_MS) * line.rate
}

/**
 * The render tick as frames advance it towards renderTarget
 * (tick-model.js advanceRenderTick: slewed, never backwards): one per
 * place that draws a seeds room, the page's RoomClock or the board worker.
 */
export class RenderTickFollower {
  /** @param {{ snaps: number }} [stats] where the snaps are counted */
  constructor (stats = { snaps: 0 }) {
    /** @type {number | null} the tick drawn last */
    this.renderTick = null
    this.lastFrameAt = null
    this.stats = stats
  }

  /**
   * The render tick at frame time `now` (fractional), or null without a line yet.
   * @param {ClockLine | null} line @param {number} now ms (page time)
   */
  advance (line, now) {
    if (line === null) return null
    const elapsed = this.lastFrameAt === null ? 0 : Math.max(0, now - this.lastFrameAt)
    this.lastFrameAt = now
    this.renderTick = advanceRenderTick(this.renderTick, renderTarget(line, now), elapsed, line.rate, this.stats)
    return this.renderTick
  }
}
