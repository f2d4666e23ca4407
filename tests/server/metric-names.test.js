import { describe, it, expect } from 'vitest'
import fs from 'node:fs'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { createMetrics, METRIC_PREFIX } from '../../server/metrics.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')
const read = (file) => fs.readFileSync(path.join(ROOT, file), 'utf8')

/** What reads the server's /metrics by name: the load-test sampler and the soak script. */
const READERS = ['loadtest/driver/metrics-sampler.js', 'scripts/soak.js']

/** Every metric family and series name in a Prometheus text exposition (a histogram, its _bucket, _sum and _count). */
function seriesNames (text) {
  const names = new Set()
  for (const line of text.split('\n')) {
    const family = /^# TYPE (\S+)/.exec(line)
    if (family) names.add(family[1])
    else if (line && !line.startsWith('#')) names.add(/^[a-zA-Z_:][a-zA-Z0-9_:]*/.exec(line)[0])
  }
  return names
}

const namesIn = (text) => new Set(text.match(/\bplinko_[a-z0-9_]+/g) ?? [])

describe('metric names', () => {
  it('have one prefix, prom-client\'s process and Node.js metrics included', async () => {
    const metrics = createMetrics()
    const names = seriesNames(await metrics.registry.metrics())
    for (const name of ['plinko_process_cpu_seconds_total', 'plinko_process_resident_memory_bytes', 'plinko_nodejs_heap_size_used_bytes', 'plinko_nodejs_eventloop_lag_p99_seconds', 'plinko_ticks_dropped_total']) {
      expect(names, name).toContain(name)
    }
    for (const name of names) {
      expect(name.startsWith(METRIC_PREFIX), name).toBe(true)
      expect(name, 'a doubled prefix').not.toMatch(/^plinko_process_process_|^plinko_process_nodejs_|^plinko_plinko_/)
    }
  })

  it('that the load-test sampler, the soak script and the manual (README, docs/) name are ones the server exposes', async () => {
    const names = seriesNames(await createMetrics().registry.metrics())
    for (const file of READERS) {
      const wanted = namesIn(read(file))
      expect(wanted.size, `${file} reads metrics by name`).toBeGreaterThan(3)
      for (const name of wanted) expect(names, `${file} reads ${name}`).toContain(name)
    }
    // The README also names k6's own metrics (loadtest/k6-lib/), which the server does not expose.
    const k6Metrics = new Set([...read('loadtest/k6-lib/player-metrics.js').matchAll(/new (?:Counter|Trend|Rate|Gauge)\('([^']+)'/g)].map((m) => m[1]))
    const manual = ['README.md', ...fs.readdirSync(path.join(ROOT, 'docs')).filter((name) => name.endsWith('.md')).map((name) => `docs/${name}`)]
    // plinko_verify is verifier-python's package (docs name its modules), not a metric.
    const documented = [...namesIn(manual.map(read).join('\n'))].filter((name) => !k6Metrics.has(name) && name !== 'plinko_verify')
    expect(documented).toContain('plinko_ticks_dropped_total')
    for (const name of documented) expect(names, `the README or docs/ name ${name}`).toContain(name)
  })
})
