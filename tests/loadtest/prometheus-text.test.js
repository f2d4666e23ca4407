import { describe, it, expect } from 'vitest'
import { parsePrometheusText, scalar, byLabel, histogramBuckets, subtractBuckets, bucketQuantile, fractionAtMost, countAbove } from '../../loadtest/driver/prometheus-text.js'

const TEXT = `# HELP plinko_ws_clients Open WebSocket connections
# TYPE plinko_ws_clients gauge
plinko_ws_clients 42
plinko_errors_total{code="E_BAD_BET"} 3
plinko_errors_total{code="E_RATE_LIMITED"} 2
plinko_tick_duration_seconds_bucket{le="0.001"} 50
plinko_tick_duration_seconds_bucket{le="0.008"} 99
plinko_tick_duration_seconds_bucket{le="+Inf"} 100
plinko_tick_duration_seconds_sum 0.2
plinko_tick_duration_seconds_count 100
`

describe('Prometheus text from /metrics', () => {
  const samples = parsePrometheusText(TEXT)

  it('reads gauges, labelled counters and histogram buckets', () => {
    expect(scalar(samples, 'plinko_ws_clients')).toBe(42)
    expect(scalar(samples, 'missing')).toBeNull()
    expect(byLabel(samples, 'plinko_errors_total', 'code')).toEqual({ E_BAD_BET: 3, E_RATE_LIMITED: 2 })
    expect(histogramBuckets(samples, 'plinko_tick_duration_seconds')).toEqual([{ le: 0.001, count: 50 }, { le: 0.008, count: 99 }, { le: Infinity, count: 100 }])
  })

  it('computes quantiles and fractions of an interval', () => {
    const later = [{ le: 0.001, count: 150 }, { le: 0.008, count: 298 }, { le: Infinity, count: 300 }]
    const interval = subtractBuckets(later, histogramBuckets(samples, 'plinko_tick_duration_seconds'))
    expect(interval.map((b) => b.count)).toEqual([100, 199, 200])
    expect(bucketQuantile(interval, 0.5)).toBeCloseTo(0.001)
    expect(bucketQuantile(interval, 0.99)).toBeCloseTo(0.001 + 0.007 * (198 - 100) / 99)
    expect(bucketQuantile(interval, 1)).toBe(0.008) // the +Inf bucket reports the highest finite bound
    expect(fractionAtMost(interval, 0.008)).toBeCloseTo(0.995)
    expect(countAbove(interval, 0.008)).toBe(1) // only in +Inf
    expect(countAbove(interval, 0.001)).toBe(100)
    expect(countAbove(interval, 0.0001)).toBe(200) // below every bound: all of them
    expect(countAbove([], 0.05)).toBeNull()
    expect(bucketQuantile([{ le: 1, count: 0 }], 0.5)).toBeNull()
  })
})
