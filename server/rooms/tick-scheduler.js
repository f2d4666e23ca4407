import { DEFAULT_TIMESTEP } from '../../engine/index.js'

/** Ticks per simulated second: every room steps the engine's fixed 1/60 s per tick. */
export const SIMULATION_HZ = Math.round(1 / DEFAULT_TIMESTEP)

const SECOND_NS = 1_000_000_000n
const MS_NS = 1_000_000n

/**
 * The one clock of the process: runs `onTick` exactly `tickRate` times per
 * second of monotonic time, however late the timers fire. Elapsed time from
 * process.hrtime.bigint() goes into an integer accumulator (in ns × tickRate,
 * so 1/60 s is exact and nothing drifts); each tick takes one second's worth
 * out. Timers only wake the loop. After a stall it catches up at most
 * `maxCatchUp` ticks per wake and drops (and counts) the rest, so a long
 * pause cannot snowball into an ever longer one.
 */
export class TickScheduler {
  /**
   * @param {object} options
   * @param {() => void} options.onTick
   * @param {number} [options.tickRate] ticks per second of wall time (SIMULATION_HZ; tests may go faster)
   * @param {number} [options.maxCatchUp] most ticks run per wake-up
   * @param {import('../metrics.js').Metrics} options.metrics
   * @param {{ error: Function }} options.log
   * @param {() => bigint} [options.now] monotonic ns
   * @param {(fn: () => void, ms: number) => any} [options.setTimer]
   * @param {(handle: any) => void} [options.clearTimer]
   */
  constructor ({ onTick, tickRate = SIMULATION_HZ, maxCatchUp = 10, metrics, log, now = process.hrtime.bigint, setTimer, clearTimer }) {
    if (!Number.isInteger(tickRate) || tickRate < 1) throw new RangeError('tickRate must be a positive integer')
    this.onTick = onTick
    this.rate = BigInt(tickRate)
    this.maxCatchUp = maxCatchUp
    this.metrics = metrics
    this.log = log
    this.now = now
    this.setTimer = setTimer ?? defaultSetTimer
    this.clearTimer = clearTimer ?? defaultClearTimer
    this.accumulator = 0n // ns × tickRate; one tick costs SECOND_NS
    this.last = 0n
    this.timer = null
    this.running = false
    this.ticks = 0
    this.droppedTicks = 0
    this._wake = () => this.wake()
  }

  start () {
    if (this.running) return
    this.running = true
    this.last = this.now()
    this.accumulator = 0n
    this._schedule()
  }

  stop () {
    this.running = false
    if (this.timer !== null) this.clearTimer(this.timer)
    this.timer = null
  }

  /** Runs the ticks that are due now. Public so tests can drive a fake clock. */
  wake () {
    this.timer = null
    if (!this.running) return
    const now = this.now()
    this.accumulator += (now - this.last) * this.rate
    this.last = now
    let steps = 0
    while (this.accumulator >= SECOND_NS && steps < this.maxCatchUp) {
      // How long ago this tick was due.
      const lagNs = (this.accumulator - SECOND_NS) / this.rate
      this.accumulator -= SECOND_NS
      steps++
      this._runTick(lagNs)
      if (!this.running) return
    }
    if (this.accumulator >= SECOND_NS) {
      const dropped = this.accumulator / SECOND_NS
      this.accumulator -= dropped * SECOND_NS
      this.droppedTicks += Number(dropped)
      this.metrics.droppedTicks.inc(Number(dropped))
    }
    this._schedule()
  }

  _runTick (lagNs) {
    const lagSeconds = Number(lagNs) / 1e9
    this.metrics.tickLag.observe(lagSeconds)
    this.metrics.tickLagCurrent.set(lagSeconds)
    const started = this.now()
    try {
      this.onTick()
    } catch (error) {
      // One bad tick must not stop the clock for every room.
      this.log.error({ err: error }, 'tick failed')
    }
    this.ticks++
    this.metrics.ticks.inc()
    this.metrics.tickDuration.observe(Number(this.now() - started) / 1e9)
  }

  _schedule () {
    if (!this.running) return
    // Time spent running ticks since `last` counts towards the next one.
    const untilNextNs = (SECOND_NS - this.accumulator) / this.rate - (this.now() - this.last)
    // setTimeout is coarse (≥ 1 ms, often late): sleep for whole ms, then poll the last fraction.
    const ms = untilNextNs > 0n ? Number(untilNextNs / MS_NS) : 0
    this.timer = this.setTimer(this._wake, ms)
  }
}

function defaultSetTimer (fn, ms) {
  return ms >= 1 ? { timeout: setTimeout(fn, ms) } : { immediate: setImmediate(fn) }
}

function defaultClearTimer (handle) {
  if (handle.timeout) clearTimeout(handle.timeout)
  else clearImmediate(handle.immediate)
}
