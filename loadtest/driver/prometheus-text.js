/**
 * Reads the Prometheus text exposition format (what GET /metrics returns)
 * and computes quantiles from histogram buckets.
 */

/**
 * @param {string} text
 * @returns {Map<string, { labels: Record<string, string>, value: number }[]>} samples by metric name
 */
export function parsePrometheusText (text) {
  const samples = new Map()
  for (const line of text.split('\n')) {
    if (line === '' || line.startsWith('#')) continue
    const match = /^([a-zA-Z_:][a-zA-Z0-9_:]*)(\{[^}]*\})?\s+(\S+)/.exec(line)
    if (!match) continue
    const [, name, labelText, valueText] = match
    const labels = {}
    if (labelText) {
      for (const [, key, value] of labelText.matchAll(/([a-zA-Z_][a-zA-Z0-9_]*)="((?:[^"\\]|\\.)*)"/g)) labels[key] = value.replace(/\\(.)/g, (_, c) => (c === 'n' ? '\n' : c))
    }
    const value = valueText === '+Inf' ? Infinity : valueText === '-Inf' ? -Infinity : Number(valueText)
    let list = samples.get(name)
    if (!list) samples.set(name, (list = []))
    list.push({ labels, value })
  }
  return samples
}

/**
 * The value of a metric without labels (or the sum over all its label sets).
 * @param {ReturnType<typeof parsePrometheusText>} samples @param {string} name
 * @returns {number | null}
 */
export function scalar (samples, name) {
  const list = samples.get(name)
  if (!list || list.length === 0) return null
  return list.reduce((sum, sample) => sum + sample.value, 0)
}

/** Values of a labelled counter by one label. @returns {Record<string, number>} */
export function byLabel (samples, name, label) {
  const out = {}
  for (const sample of samples.get(name) ?? []) out[sample.labels[label] ?? ''] = (out[sample.labels[label] ?? ''] ?? 0) + sample.value
  return out
}

/**
 * A histogram's cumulative buckets, sorted by upper bound.
 * @returns {{ le: number, count: number }[]}
 */
export function histogramBuckets (samples, name) {
  return (samples.get(`${name}_bucket`) ?? [])
    .map((sample) => ({ le: sample.labels.le === '+Inf' ? Infinity : Number(sample.labels.le), count: sample.value }))
    .sort((a, b) => a.le - b.le)
}

/** Bucket counts of `later` minus `earlier` (what happened between two scrapes). */
export function subtractBuckets (later, earlier) {
  const before = new Map(earlier.map((b) => [b.le, b.count]))
  return later.map((b) => ({ le: b.le, count: b.count - (before.get(b.le) ?? 0) }))
}

/**
 * The q-quantile of cumulative buckets, interpolated linearly inside the
 * bucket it falls in (as Prometheus' histogram_quantile does). Falls in the
 * +Inf bucket: the highest finite bound. No observations: null.
 * @param {{ le: number, count: number }[]} buckets cumulative @param {number} q 0..1
 */
export function bucketQuantile (buckets, q) {
  if (buckets.length === 0) return null
  const total = buckets[buckets.length - 1].count
  if (!(total > 0)) return null
  const rank = q * total
  let lowerBound = 0
  let lowerCount = 0
  for (const bucket of buckets) {
    if (bucket.count >= rank) {
      if (bucket.le === Infinity) return lowerBound
      const inBucket = bucket.count - lowerCount
      return inBucket > 0 ? lowerBound + (bucket.le - lowerBound) * (rank - lowerCount) / inBucket : bucket.le
    }
    lowerBound = bucket.le
    lowerCount = bucket.count
  }
  return lowerBound
}

/** Fraction of observations ≤ `bound` (exact when `bound` is a bucket bound). */
export function fractionAtMost (buckets, bound) {
  if (buckets.length === 0) return null
  const total = buckets[buckets.length - 1].count
  if (!(total > 0)) return null
  return countAtMost(buckets, bound) / total
}

/** Observations above `bound` (exact when `bound` is a bucket bound): what a histogram counts beyond a goal. */
export function countAbove (buckets, bound) {
  if (buckets.length === 0) return null
  return buckets[buckets.length - 1].count - countAtMost(buckets, bound)
}

/** Observations ≤ `bound`: the cumulative count of the last bucket whose bound is within it. */
function countAtMost (buckets, bound) {
  let count = 0
  for (const bucket of buckets) if (bucket.le <= bound) count = bucket.count
  return count
}
