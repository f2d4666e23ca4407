/**
 * The operator's charts: a room's bucket distribution against the
 * calibrated one, and its measured RTP over time against the calibrated
 * RTP. Built with the project's one SVG writer (charts/svg.js, served at
 * /charts/) and handed to the page as DOM nodes (no markup strings).
 */
import { svg, svgElement } from '/charts/svg.js'

const COLORS = { measured: '#ff5a8a', calibrated: '#ffc400', band: 'rgba(255, 90, 138, 0.18)', axis: '#46518a', text: '#98a3cf' }

function text (x, y, content, attributes = {}) {
  return svg('text', { x, y, fill: COLORS.text, 'font-size': 11, 'font-family': 'system-ui, sans-serif', ...attributes }, content)
}

/** A horizontal line across the plot at y, labelled at its left end. */
function gridLine (left, right, y, label) {
  return [
    svg('line', { x1: left, x2: right, y1: y, y2: y, stroke: COLORS.axis, 'stroke-width': 1 }),
    text(left - 4, y + 4, label, { 'text-anchor': 'end', class: 'tick-label' })
  ]
}

/**
 * Bars: share of the room's settled drops per bucket; markers: the share
 * calibration predicts (calibrationOf(rows, engineVersion).bucketCounts).
 * @param {number[]} counts settled drops per bucket
 * @param {number[]} calibrated calibrated counts per bucket
 * @returns {SVGSVGElement}
 */
export function bucketChart (counts, calibrated) {
  const width = 560
  const height = 220
  const pad = { left: 40, right: 10, top: 12, bottom: 26 }
  const total = counts.reduce((a, b) => a + b, 0)
  const calibratedTotal = calibrated.reduce((a, b) => a + b, 0)
  const measuredShare = counts.map((c) => (total === 0 ? 0 : c / total))
  const expectedShare = calibrated.map((c) => c / calibratedTotal)
  const top = Math.max(0.05, ...measuredShare, ...expectedShare) * 1.1
  const plotW = width - pad.left - pad.right
  const plotH = height - pad.top - pad.bottom
  const band = plotW / counts.length
  const y = (share) => pad.top + plotH * (1 - share / top)
  return svgElement(svg('svg', { viewBox: `0 0 ${width} ${height}`, class: 'chart', role: 'img', 'aria-label': 'bucket distribution, measured against calibrated' },
    [0, top / 2, top].map((share) => gridLine(pad.left, width - pad.right, y(share), `${(share * 100).toFixed(1)}%`)),
    counts.map((count, i) => {
      const x = pad.left + i * band
      const barTop = y(measuredShare[i])
      return [
        svg('rect', { x: x + band * 0.15, y: barTop, width: band * 0.7, height: pad.top + plotH - barTop, fill: COLORS.measured, rx: 2 },
          svg('title', {}, `bucket ${i}: ${count} drops (${(measuredShare[i] * 100).toFixed(2)}%), calibrated ${(expectedShare[i] * 100).toFixed(2)}%`)),
        svg('line', { x1: x + band * 0.08, x2: x + band * 0.92, y1: y(expectedShare[i]), y2: y(expectedShare[i]), stroke: COLORS.calibrated, 'stroke-width': 2.5 }),
        text(x + band / 2, height - 8, String(i), { 'text-anchor': 'middle' })
      ]
    })))
}

/**
 * Measured RTP (per drop, with its 95% confidence band) at each refresh,
 * against the calibrated RTP as a horizontal line.
 * @param {{ drops: number, rtp: number, low: number, high: number }[]} samples oldest first
 * @param {number} calibrated
 * @returns {SVGSVGElement}
 */
export function rtpChart (samples, calibrated) {
  const width = 560
  const height = 200
  const pad = { left: 48, right: 10, top: 12, bottom: 26 }
  const plotW = width - pad.left - pad.right
  const plotH = height - pad.top - pad.bottom
  const points = samples.filter((s) => Number.isFinite(s.rtp))
  const values = [calibrated, ...points.map((s) => s.rtp)]
  for (const s of points) if (Number.isFinite(s.low)) values.push(s.low, s.high)
  // Round ticks (steps of 1, 2 or 5 × 10^k percent, so 100% is one when in range); an RTP is never below 0.
  const ticks = niceTicks(Math.max(0, Math.min(...values)), Math.max(...values))
  const min = ticks[0]
  const max = ticks[ticks.length - 1]
  const decimals = Math.max(0, -Math.floor(Math.log10((ticks[1] - ticks[0]) * 100) + 1e-9))
  const maxDrops = Math.max(1, ...points.map((s) => s.drops))
  const x = (drops) => pad.left + plotW * (drops / maxDrops)
  const y = (value) => pad.top + plotH * (1 - (value - min) / (max - min))
  const upper = points.filter((s) => Number.isFinite(s.high)).map((s) => `${x(s.drops)},${y(s.high)}`)
  const lower = points.filter((s) => Number.isFinite(s.low)).map((s) => `${x(s.drops)},${y(s.low)}`).reverse()
  const last = points[points.length - 1]
  return svgElement(svg('svg', { viewBox: `0 0 ${width} ${height}`, class: 'chart', role: 'img', 'aria-label': 'measured RTP against calibrated RTP' },
    ticks.map((value) => gridLine(pad.left, width - pad.right, y(value), `${(value * 100).toFixed(decimals)}%`)),
    text(width - pad.right, height - 8, `${maxDrops} settled drops`, { 'text-anchor': 'end' }),
    points.length > 0 && [
      upper.length > 1 && svg('polygon', { points: [...upper, ...lower].join(' '), fill: COLORS.band }),
      svg('polyline', { points: points.map((s) => `${x(s.drops)},${y(s.rtp)}`).join(' '), fill: 'none', stroke: COLORS.measured, 'stroke-width': 2 }),
      svg('circle', { cx: x(last.drops), cy: y(last.rtp), r: 3.5, fill: COLORS.measured })
    ],
    svg('line', { x1: pad.left, x2: width - pad.right, y1: y(calibrated), y2: y(calibrated), stroke: COLORS.calibrated, 'stroke-width': 2, 'stroke-dasharray': '6 4' }),
    text(pad.left + 4, y(calibrated) - 5, `calibrated ${(calibrated * 100).toFixed(2)}%`, { fill: COLORS.calibrated })))
}

/** A legend row: [label, colour] pairs. @param {[string, string][]} items */
export function legend (items) {
  const row = document.createElement('div')
  row.className = 'legend'
  for (const [label, color] of items) {
    const item = document.createElement('span')
    const swatch = document.createElement('i')
    swatch.style.background = color
    item.append(swatch, label)
    row.append(item)
  }
  return row
}

export const CHART_COLORS = COLORS

/**
 * Round axis ticks covering [low, high] (fractions: 0.99 is 99%): a step
 * of 1, 2 or 5 × 10^k, about four intervals, the ends snapped outwards to
 * it; at least 1% of span. @param {number} low @param {number} high @returns {number[]}
 */
export function niceTicks (low, high) {
  const span = Math.max(0.01, high - low)
  const rough = span / 4
  const power = 10 ** Math.floor(Math.log10(rough))
  const step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= rough)
  // Integer steps of 1/100000 keep 0.99 + 0.01 from drifting.
  const unit = Math.round(step * 1e5)
  const first = Math.floor(Math.round(low * 1e5) / unit) * unit
  const last = Math.ceil(Math.round(high * 1e5) / unit) * unit
  const ticks = []
  for (let t = first; t <= last; t += unit) ticks.push(t / 1e5)
  if (ticks.length < 2) ticks.push((last + unit) / 1e5)
  return ticks
}
