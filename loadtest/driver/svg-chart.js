/**
 * A self-contained SVG of a run's time series: stacked panels sharing the
 * time axis, the steady window shaded. No dependencies, no scripts.
 */

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
  const out = [
    `<svg xmlns="http://www.w3.org/2000/svg" width="${WIDTH}" height="${height}" viewBox="0 0 ${WIDTH} ${height}" font-family="sans-serif" font-size="11">`,
    `<rect width="${WIDTH}" height="${height}" fill="#fff"/>`,
    `<text x="${MARGIN.left}" y="22" font-size="14" font-weight="bold">${escape(title)}</text>`
  ]
  panels.forEach((panel, index) => {
    const top = MARGIN.top + index * (PANEL_HEIGHT + MARGIN.gap)
    const values = panel.lines.flatMap((line) => points.map((p) => p[line.key])).filter((v) => v !== null && v !== undefined && Number.isFinite(v))
    const yMax = niceCeiling(Math.max(1e-9, ...values, panel.goal ? panel.goal.value * 1.2 : 0))
    const y = (v) => top + PANEL_HEIGHT - (Math.min(v, yMax) / yMax) * PANEL_HEIGHT
    if (window) out.push(`<rect x="${x(window.from).toFixed(1)}" y="${top}" width="${(x(window.to) - x(window.from)).toFixed(1)}" height="${PANEL_HEIGHT}" fill="#f2f2f2"/>`)
    for (let i = 0; i <= 5; i++) {
      const v = (yMax * i) / 5
      out.push(`<line x1="${MARGIN.left}" x2="${MARGIN.left + plotWidth}" y1="${y(v).toFixed(1)}" y2="${y(v).toFixed(1)}" stroke="#ddd"/>`)
      out.push(`<text x="${MARGIN.left - 6}" y="${(y(v) + 4).toFixed(1)}" text-anchor="end" fill="#555">${formatTick(v)}</text>`)
    }
    out.push(`<text x="${MARGIN.left}" y="${top - 8}" font-weight="bold">${escape(panel.title)} <tspan font-weight="normal" fill="#555">(${escape(panel.unit)})</tspan></text>`)
    if (panel.goal) {
      out.push(`<line x1="${MARGIN.left}" x2="${MARGIN.left + plotWidth}" y1="${y(panel.goal.value).toFixed(1)}" y2="${y(panel.goal.value).toFixed(1)}" stroke="#000" stroke-dasharray="5,4"/>`)
      out.push(`<text x="${MARGIN.left + plotWidth + 8}" y="${(y(panel.goal.value) + 4).toFixed(1)}">${escape(panel.goal.label)}</text>`)
    }
    panel.lines.forEach((line, lineIndex) => {
      const color = COLORS[lineIndex % COLORS.length]
      const segments = []
      let current = []
      for (const p of points) {
        const v = p[line.key]
        if (v === null || v === undefined || !Number.isFinite(v)) {
          if (current.length) segments.push(current)
          current = []
          continue
        }
        current.push(`${x(p.t).toFixed(1)},${y(v).toFixed(1)}`)
      }
      if (current.length) segments.push(current)
      for (const segment of segments) out.push(`<polyline fill="none" stroke="${color}" stroke-width="1.5" points="${segment.join(' ')}"/>`)
      out.push(`<rect x="${MARGIN.left + plotWidth + 8}" y="${top + 8 + lineIndex * 16}" width="10" height="3" fill="${color}"/>`)
      out.push(`<text x="${MARGIN.left + plotWidth + 22}" y="${top + 13 + lineIndex * 16}">${escape(line.label)}</text>`)
    })
    out.push(`<rect x="${MARGIN.left}" y="${top}" width="${plotWidth}" height="${PANEL_HEIGHT}" fill="none" stroke="#999"/>`)
  })
  const bottom = height - MARGIN.bottom
  for (let i = 0; i <= 10; i++) {
    const t = (tMax * i) / 10
    out.push(`<text x="${x(t).toFixed(1)}" y="${bottom + 14}" text-anchor="middle" fill="#555">${Math.round(t)}</text>`)
  }
  out.push(`<text x="${MARGIN.left + plotWidth / 2}" y="${bottom + 30}" text-anchor="middle">seconds${window ? ' (grey: steady window)' : ''}</text>`)
  out.push('</svg>')
  return out.join('\n') + '\n'
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

function escape (text) {
  return String(text).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c])
}
