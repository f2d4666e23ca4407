import { describe, it, expect } from 'vitest'
import { TickScheduler } from '../../server/rooms/tick-scheduler.js'
import { createMetrics } from '../../server/metrics.js'

/** A scheduler on a fake monotonic clock whose timers the test fires by hand. */
function fakeScheduler (options = {}) {
  const clock = { now: 0n, timers: [] }
  const metrics = createMetrics({ defaultMetrics: false })
  let ticks = 0
  const scheduler = new TickScheduler({
    onTick: options.onTick ?? (() => { ticks++ }),
    tickRate: 60,
    maxCatchUp: 10,
    metrics,
    log: { error () {} },
    now: () => clock.now,
    setTimer: (fn, ms) => { clock.timers.push(ms); return clock.timers.length },
    clearTimer: () => {}
  })
  return { scheduler, clock, metrics, ticks: () => ticks, advance (ms) { clock.now += BigInt(Math.round(ms * 1e6)); scheduler.wake() } }
}

async function counter (metrics, name) {
  return (await metrics.registry.getSingleMetric(name).get()).values[0]?.value ?? 0
}

describe('TickScheduler', () => {
  it('runs exactly 60 ticks per second of monotonic time however irregular the wake-ups (no drift)', () => {
    const { scheduler, clock, advance, ticks } = fakeScheduler()
    scheduler.start()
    let state = 12345
    const random = () => (state = (state * 1103515245 + 12345) % 2147483648) / 2147483648
    let elapsedNs = 0n
    for (let i = 0; i < 200_000; i++) {
      const ms = 1 + random() * 24 // late, early and ragged timers
      const before = clock.now
      advance(ms)
      elapsedNs += clock.now - before
      // Never ahead, never more than one tick behind.
      expect(ticks()).toBe(Number(elapsedNs * 60n / 1_000_000_000n))
    }
    expect(elapsedNs).toBeGreaterThan(3600n * 1_000_000_000n / 2n)
    expect(scheduler.droppedTicks).toBe(0)
  })

  it('asks to be woken when the next tick is due', () => {
    const { scheduler, clock, advance } = fakeScheduler()
    scheduler.start()
    expect(clock.timers.at(-1)).toBe(16) // 16.67 ms, slept in whole ms
    advance(10)
    expect(clock.timers.at(-1)).toBe(6)
    advance(6.5)
    expect(clock.timers.at(-1)).toBe(0) // under a millisecond left: poll
    advance(0.2)
    expect(clock.timers.at(-1)).toBe(16)
  })

  it('counts the time spent in ticks when choosing the next wake-up', () => {
    const fake = fakeScheduler({ onTick: () => { fake.clock.now += 9_000_000n } }) // each tick works 9 ms
    fake.scheduler.start()
    fake.advance(1000 / 60)
    // Woken on time; 9 ms of the 16.7 ms period went to the tick itself.
    expect(fake.clock.timers.at(-1)).toBe(7)
    fake.advance(7.67)
    expect(fake.clock.timers.at(-1)).toBe(7)
    expect(fake.scheduler.ticks).toBe(2)
  })

  it('catches up a stall in at most 10 ticks per wake, drops and counts the rest, and reports the lag', async () => {
    const { scheduler, advance, ticks, metrics } = fakeScheduler()
    scheduler.start()
    advance(1000) // a one-second stall: 60 ticks due
    expect(ticks()).toBe(10)
    expect(scheduler.droppedTicks).toBe(50)
    expect(await counter(metrics, 'plinko_ticks_dropped_total')).toBe(50)
    const lag = await metrics.registry.getSingleMetric('plinko_tick_lag_seconds').get()
    const sum = lag.values.find((v) => v.metricName === 'plinko_tick_lag_seconds_sum').value
    expect(sum).toBeGreaterThan(9) // the first catch-up tick was ~983 ms late
    // Afterwards the clock runs on normally from "now".
    advance(1000 / 60)
    expect(ticks()).toBe(11)
  })

  it('keeps ticking when a tick throws, and stops when asked', () => {
    let n = 0
    const log = { errors: 0, error () { this.errors++ } }
    const { scheduler, advance } = fakeScheduler({ onTick: () => { n++; if (n === 2) throw new Error('boom') } })
    scheduler.log = log
    scheduler.start()
    advance(50)
    expect(n).toBe(3)
    expect(log.errors).toBe(1)
    scheduler.stop()
    advance(1000)
    expect(n).toBe(3)
  })
})
