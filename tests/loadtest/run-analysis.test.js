import { describe, it, expect } from 'vitest'
import { steadyWindow, analyzeServerSamples, series } from '../../loadtest/driver/run-analysis.js'
import { renderChart } from '../../loadtest/driver/svg-chart.js'

/** Synthetic /metrics samples: clients ramp 0 → 100 over 10 s, hold to 30 s, leave by 35 s. */
function samples () {
  const out = []
  let ticks = 0
  for (let t = 0; t <= 40; t++) {
    const clients = t < 10 ? t * 10 : t <= 30 ? 100 : Math.max(0, 100 - (t - 30) * 20)
    ticks += 60
    out.push({
      t, ok: true, scrapeMs: 1, clients, rooms: 5, balls: clients, rss: 100e6 + clients * 50e3, heapUsed: 20e6 + clients * 20e3,
      eventLoopP99: 0.011, eventLoopMax: 0.012, tickLagCurrent: 0,
      tickBuckets: [{ le: 0.001, count: ticks * 0.9 }, { le: 0.008, count: ticks }, { le: Infinity, count: ticks }],
      lagBuckets: [{ le: 0.001, count: ticks }, { le: Infinity, count: ticks }],
      // one commit in a hundred over 50 ms: a stall of the disk
      commitBuckets: [{ le: 0.002, count: ticks * 0.98 }, { le: 0.05, count: ticks * 0.99 }, { le: Infinity, count: ticks }],
      ticks, droppedTicks: 0, drops: t * 50, settles: t * 50, bytesOut: t * 1e6, messagesOut: t * 5000, snapshotsSkipped: 0, slowClosed: 0,
      errors: {}, serverCpuS: t * 0.5, k6CpuS: t * 0.7, k6Rss: 1e9, machine: { busyS: t * 1.3, totalS: t * 2 }
    })
  }
  return out
}

describe('run analysis', () => {
  it('finds the steady window: every player connected, after a settling pause', () => {
    expect(steadyWindow(samples(), 100)).toMatchObject({ from: 13, to: 30 })
  })

  it('derives the report figures from cumulative counters', () => {
    const result = analyzeServerSamples(samples(), { expectedClients: 100, baselineIndex: 0 })
    expect(result.clients.mean).toBe(100)
    expect(result.tick.perSecond).toBeCloseTo(60)
    expect(result.tick.within8ms).toBe(1)
    // 17 s of 60 commits a second, one in a hundred over 50 ms
    expect(result.commit.perSecond).toBeCloseTo(60)
    expect(result.commit.over50ms).toBeCloseTo(0.01 * 60 * 17)
    expect(result.tick.p50).toBeLessThanOrEqual(0.001)
    expect(result.traffic.bytesPerClientPerSecond).toBeCloseTo(1e4)
    expect(result.memory.rssPerClient).toBeCloseTo(50e3)
    expect(result.cpu.server).toBeCloseTo(0.5)
    expect(result.cpu.k6).toBeCloseTo(0.7)
    expect(result.cpu.others).toBeCloseTo(0.1)
    expect(result.eventLoop.p99Median).toBeCloseTo(0.001) // the 10 ms sampling resolution is taken off
  })

  it('draws a chart without NaN', () => {
    const svg = renderChart({
      title: 'test <run>',
      points: series(samples()),
      window: { from: 13, to: 30 },
      panels: [{ title: 'players', unit: 'count', lines: [{ key: 'clients', label: 'players' }] }, { title: 'tick', unit: 'ms', lines: [{ key: 'tickP99Ms', label: 'p99' }], goal: { value: 8, label: 'goal' } }]
    })
    expect(svg).toMatch(/^<svg /)
    expect(svg).toContain('<polyline')
    expect(svg).toContain('test &lt;run&gt;')
    expect(svg).not.toMatch(/NaN|undefined|Infinity/)
  })
})
