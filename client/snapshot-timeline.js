/**
 * Playback clock and buffer for a room's snapshots.
 *
 * The server stamps every snapshot with its room tick. The timeline keeps
 * a model of the server's clock, tick ≈ offset + now · rate, fitted to the
 * *earliest* arrivals (network delay only ever makes a frame later), and
 * renders at that estimate minus a playout delay:
 *
 *   delay = max(100 ms, snapshot interval + 2.5 · mean lateness + one frame)
 *
 * where lateness is how much later than the clock model each snapshot
 * arrived: with a steady network the buffer is ~100 ms, with jitter it
 * grows just enough that the snapshot after the render point is almost
 * always there. The render clock advances by the frame time and is slewed
 * (by at most ±10% of its speed) towards the target, so it never jumps
 * or runs backwards; it snaps only after a long stall (a hidden tab).
 * Snapshots that arrive out of order are slotted in by tick; those older
 * than the one being rendered from are stale and dropped.
 */

import { TickModel, advanceRenderTick } from './tick-model.js'

/** A slower network than this would be unplayable anyway. */
const MAX_DELAY_MS = 1000
const MIN_DELAY_MS = 100
const FRAME_MS = 1000 / 60
/** Clock samples of this last stretch estimate the server's real tick rate (tests run servers faster than 60 Hz). */
const RATE_WINDOW_MS = 4000
const RATE_MAX_SAMPLES = 512
const RATE_MIN_SAMPLES = 8
const MAX_BUFFERED = 120

/** @typedef {import('/protocol/snapshot-codec.js').Snapshot} Snapshot */

export class SnapshotTimeline {
  /**
   * @param {object} options
   * @param {number} options.tickRate nominal ticks per second (the server's `tickRate`)
   * @param {number} options.snapshotEvery ticks between snapshots
   */
  constructor ({ tickRate, snapshotEvery }) {
    this.clock = new TickModel({ tickRate, windowMs: RATE_WINDOW_MS, maxSamples: RATE_MAX_SAMPLES, minSamples: RATE_MIN_SAMPLES })
    this.snapshotEvery = snapshotEvery
    /** @type {Snapshot[]} ascending by tick */
    this.buffer = []
    this.stats = { received: 0, stale: 0, duplicates: 0, outOfOrder: 0, snaps: 0, underruns: 0 }
    this.reset()
  }

  /** Forgets the clock and the buffer (a new room or a new connection). */
  reset () {
    this.buffer.length = 0
    this.clock.reset()
    this.delayMs = MIN_DELAY_MS
    /** @type {number | null} */
    this.renderTick = null
    this.lastFrameAt = null
    this.consumedTick = -1
  }

  /** ticks per ms, as measured */
  get rate () { return this.clock.rate }
  /** mean lateness of frames behind the clock model (ms) */
  get jitterMs () { return this.clock.jitterMs }

  /**
   * A clock observation: the server was at `tick` when it sent something
   * that arrived at `now` (a snapshot, or the tick in `joined`).
   * @param {number} tick @param {number} now ms (performance.now())
   */
  observe (tick, now) {
    this.clock.observe(tick, now)
  }

  /**
   * Adds a snapshot to the buffer.
   * @param {Snapshot} snapshot @param {number} now ms
   * @returns {'accepted' | 'stale' | 'duplicate'}
   */
  push (snapshot, now) {
    this.stats.received++
    this.observe(snapshot.tick, now)
    if (snapshot.tick <= this.consumedTick) {
      this.stats.stale++
      return 'stale'
    }
    const buffer = this.buffer
    let i = buffer.length
    while (i > 0 && buffer[i - 1].tick > snapshot.tick) i--
    if (i > 0 && buffer[i - 1].tick === snapshot.tick) {
      this.stats.duplicates++
      return 'duplicate'
    }
    if (i < buffer.length) this.stats.outOfOrder++
    buffer.splice(i, 0, snapshot)
    if (buffer.length > MAX_BUFFERED) buffer.splice(0, buffer.length - MAX_BUFFERED)
    return 'accepted'
  }

  /** The server tick the clock model expects now. @param {number} now */
  serverTickAt (now) {
    return this.clock.tickAt(now)
  }

  /** Playout delay for the jitter measured so far (ms). */
  targetDelayMs () {
    const intervalMs = this.snapshotEvery / this.rate
    const wanted = intervalMs + 2.5 * this.jitterMs + FRAME_MS
    return Math.min(MAX_DELAY_MS, Math.max(MIN_DELAY_MS, wanted))
  }

  /**
   * Advances the render clock to frame time `now` and returns the tick to
   * render (fractional), or null before the first clock observation.
   * @param {number} now ms
   */
  advance (now) {
    const serverTick = this.serverTickAt(now)
    if (serverTick === null) return null
    this.delayMs = this.targetDelayMs()
    const target = serverTick - this.delayMs * this.rate
    const elapsed = this.lastFrameAt === null ? 0 : Math.max(0, now - this.lastFrameAt)
    this.lastFrameAt = now
    this.renderTick = advanceRenderTick(this.renderTick, target, elapsed, this.rate, this.stats)
    const newest = this.buffer.length > 0 ? this.buffer[this.buffer.length - 1].tick : -1
    if (newest >= 0 && this.renderTick > newest) this.stats.underruns++
    return this.renderTick
  }

  /**
   * The snapshots around `tick`: `a` the last at or before it, `b` the
   * first after it (either may be null). Older snapshots than `a` are
   * released: nothing will render before `tick` again.
   * @param {number} tick
   * @returns {{ a: Snapshot | null, b: Snapshot | null }}
   */
  bracket (tick) {
    const buffer = this.buffer
    let i = 0
    while (i < buffer.length && buffer[i].tick <= tick) i++
    const a = i > 0 ? buffer[i - 1] : null
    if (i > 1) buffer.splice(0, i - 1)
    if (a) this.consumedTick = Math.max(this.consumedTick, a.tick)
    return { a, b: buffer.find((s) => s.tick > tick) ?? null }
  }
}
