import { svg, svgDocument } from '../charts/svg.js'

/**
 * An SVG bar chart of a bucket distribution: measured share per bucket,
 * reference shares as markers (the calibrated share, the binomial, another
 * version's), and each bucket's multiplier. A log scale shows the tails,
 * where boards differ most.
 * @param {object} chart
 * @param {string} chart.title
 * @param {number[]} chart.counts drops per bucket
 * @param {number[]} chart.multipliers
 * @param {number[]} [chart.expected] calibrated probability per bucket (a marker labelled "calibrated share")
 * @param {{ label: string, shares: number[], color: string }[]} [chart.markers] more reference shares
 * @param {string} [chart.barLabel] legend of the bars
 * @param {boolean} [chart.logScale] share axis in powers of ten
 * @returns {string} SVG document
 */
export function distributionChartSvg ({ title, counts, multipliers, expected, markers = [], barLabel = 'measured share', logScale = false }) {
  const total = counts.reduce((a, b) => a + b, 0) || 1
  const shares = counts.map((c) => c / total)
  const series = [...(expected ? [{ label: 'calibrated share', shares: expected, color: '#d04a4a' }] : []), ...markers]
  const all = [...shares, ...series.flatMap((s) => s.shares)]
  const top = Math.max(...all) * 1.1 || 1
  const positive = all.filter((s) => s > 0)
  // One decade below the rarest share, so even the rarest bucket's bar shows.
  const floorDecade = Math.floor(Math.log10(Math.min(...positive, top))) - 1
  const topDecade = Math.ceil(Math.log10(top))
  const width = 720
  const height = 360
  const left = 56
  const bottom = 300
  const plotHeight = 250
  const barWidth = (width - left - 20) / counts.length
  const y = logScale
    ? (share) => bottom - (Math.log10(Math.max(share, 10 ** floorDecade)) - floorDecade) / (topDecade - floorDecade) * plotHeight
    : (share) => bottom - (share / top) * plotHeight
  const ticks = logScale
    ? Array.from({ length: topDecade - floorDecade + 1 }, (_, i) => 10 ** (floorDecade + i))
    : Array.from({ length: 5 }, (_, i) => (top * i) / 4)
  const tickLabel = (share) => logScale
    ? (share >= 0.99e-4 ? `${Number((share * 100).toPrecision(1))}%` : share.toExponential(0))
    : `${(share * 100).toFixed(1)}%`
  const f = (n) => n.toFixed(1)
  const chart = svg('svg', { width, height, viewBox: `0 0 ${width} ${height}`, 'font-family': 'sans-serif', 'font-size': 11 },
    svg('rect', { width, height, fill: '#fff' }),
    svg('text', { x: width / 2, y: 20, 'text-anchor': 'middle', 'font-size': 14 }, title),
    ticks.map((share) => [
      svg('line', { x1: left, x2: width - 20, y1: f(y(share)), y2: f(y(share)), stroke: '#eee' }),
      svg('text', { x: left - 6, y: f(y(share) + 4), 'text-anchor': 'end' }, tickLabel(share))
    ]),
    shares.map((share, i) => {
      const x = left + i * barWidth
      return [
        svg('rect', { x: f(x + 2), y: f(y(share)), width: f(barWidth - 4), height: f(bottom - y(share)), fill: '#4a7bd0' },
          svg('title', {}, `bucket ${i}: ${(share * 100).toFixed(4)}% (${counts[i]})`)),
        series.map((s) => svg('line', { x1: f(x + 2), x2: f(x + barWidth - 2), y1: f(y(s.shares[i])), y2: f(y(s.shares[i])), stroke: s.color, 'stroke-width': 2 },
          svg('title', {}, `${s.label}: ${(s.shares[i] * 100).toFixed(4)}%`))),
        svg('text', { x: f(x + barWidth / 2), y: bottom + 14, 'text-anchor': 'middle' }, i),
        svg('text', { x: f(x + barWidth / 2), y: bottom + 30, 'text-anchor': 'middle', fill: '#555' }, `${multipliers[i]}x`)
      ]
    }),
    legend(left, height - 8, [[`■ ${barLabel}`, '#4a7bd0', barLabel], ...series.map((s) => [`— ${s.label}`, s.color, s.label])]),
    svg('text', { x: width - 20, y: height - 8, 'text-anchor': 'end', fill: '#555' }, 'bucket / multiplier'))
  return svgDocument(chart)
}

/** Legend entries side by side from x, each as wide as its label. @param {[string, string, string][]} entries [text, colour, label] */
function legend (x, y, entries) {
  return entries.map(([text, fill, label]) => {
    const entry = svg('text', { x, y, fill }, text)
    x += 30 + label.length * 6
    return entry
  })
}
