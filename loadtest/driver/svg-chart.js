/**
 * A self-contained SVG of a run's time series: stacked panels sharing the
 * time axis, the steady window shaded. No scripts; written with the
 * project's one SVG writer (charts/svg.js).
 */
import { svg, svgDocument } from '../../charts/svg.js'

const WIDTH = 960
const PANEL_HEIGHT = 150
const MARGIN = { left: 64, right: 150, top: 54, gap: 34, bottom: 36 }
const COLORS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e']

/**
 * @param {object} options
 * @param {string} options.title
 * @param {{ t: number, [key: string]: number | null }[]} options.points
 * @param {{ title: string, unit: string, lines: { key: string, label: string }[], goal?: { value: number, label: string } }[]} options.panels
 * @param {{ from: number, to: number } | null} [options.window] shaded
 * @returns {string}
 */
export function renderChart ({ title, points, panels, window }) {
  const height = MARGIN.top + panels.length * (PANEL_HEIGHT + MARGIN.gap) - MARGIN.gap + MARGIN.bottom
  const plotWidth = WIDTH - MARGIN.left - MARGIN.right
  const tMax = Math.max(1, ...points.map((p) => p.t))
  const x = (t) => MARGIN.left + (t / tMax) * plotWidth
  const f = (n) => n.toFixed(1)
  const bottom = height - MARGIN.bottom
  const chart = svg('svg', { width: WIDTH, height, viewBox: `0 0 ${WIDTH} ${height}`, 'font-family': 'sans-serif', 'font-size': 11 },
    svg('rect', { width: WIDTH, height, fill: '#fff' }),
    svg('text', { x: MARGIN.left, y: 22, 'font-size': 14, 'font-weight': 'bold' }, title),
    panels.map((panel, index) => {
      const top = MARGIN.top + index * (PANEL_HEIGHT + MARGIN.gap)
      const values = panel.lines.flatMap((line) => points.map((p) => p[line.key])).filter(isValue)
      const yMax = niceCeiling(Math.max(1e-9, ...values, panel.goal ? panel.goal.value * 1.2 : 0))
      const y = (v) => top + PANEL_HEIGHT - (Math.min(v, yMax) / yMax) * PANEL_HEIGHT
      return [
        window && svg('rect', { x: f(x(window.from)), y: top, width: f(x(window.to) - x(window.from)), height: PANEL_HEIGHT, fill: '#f2f2f2' }),
        Array.from({ length: 6 }, (_, i) => (yMax * i) / 5).map((v) => [
          svg('line', { x1: MARGIN.left, x2: MARGIN.left + plotWidth, y1: f(y(v)), y2: f(y(v)), stroke: '#ddd' }),
          svg('text', { x: MARGIN.left - 6, y: f(y(v) + 4), 'text-anchor': 'end', fill: '#555' }, formatTick(v))
        ]),
        svg('text', { x: MARGIN.left, y: top - 8, 'font-weight': 'bold' }, `${panel.title} `, svg('tspan', { 'font-weight': 'normal', fill: '#555' }, `(${panel.unit})`)),
        panel.goal && [
          svg('line', { x1: MARGIN.left, x2: MARGIN.left + plotWidth, y1: f(y(panel.goal.value)), y2: f(y(panel.goal.value)), stroke: '#000', 'stroke-dasharray': '5,4' }),
          svg('text', { x: MARGIN.left + plotWidth + 8, y: f(y(panel.goal.value) + 4) }, panel.goal.label)
        ],
        panel.lines.map((line, lineIndex) => {
          const color = COLORS[lineIndex % COLORS.length]
          return [
            segments(points, line.key).map((segment) => svg('polyline', { fill: 'none', stroke: color, 'stroke-width': 1.5, points: segment.map((p) => `${f(x(p.t))},${f(y(p[line.key]))}`).join(' ') })),
            svg('rect', { x: MARGIN.left + plotWidth + 8, y: top + 8 + lineIndex * 16, width: 10, height: 3, fill: color }),
            svg('text', { x: MARGIN.left + plotWidth + 22, y: top + 13 + lineIndex * 16 }, line.label)
          ]
        }),
        svg('rect', { x: MARGIN.left, y: top, width: plotWidth, height: PANEL_HEIGHT, fill: 'none', stroke: '#999' })
      ]
    }),
    Array.from({ length: 11 }, (_, i) => (tMax * i) / 10).map((t) =>
      svg('text', { x: f(x(t)), y: bottom + 14, 'text-anchor': 'middle', fill: '#555' }, Math.round(t))),
    svg('text', { x: MARGIN.left + plotWidth / 2, y: bottom + 30, 'text-anchor': 'middle' }, `seconds${window ? ' (grey: steady window)' : ''}`))
  return svgDocument(chart)
}

const isValue = (v) => v !== null && v !== undefined && Number.isFinite(v)

/** The runs of points where `key` has a value: a gap in the samples is a gap in the line. */
function segments (points, key) {
  const runs = []
  let current = []
  for (const p of points) {
    if (isValue(p[key])) {
      current.push(p)
    } else if (current.length) {
      runs.push(current)
      current = []
    }
  }
  if (current.length) runs.push(current)
  return runs
}

function niceCeiling (value) {
  const power = 10 ** Math.floor(Math.log10(value))
  for (const step of [1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10]) if (value <= step * power) return step * power
  return 10 * power
}

function formatTick (v) {
  if (v === 0) return '0'
  if (v >= 1000) return `${+(v / 1000).toFixed(1)}k`
  return String(+v.toPrecision(3))
}
