/**
 * An SVG bar chart of a bucket distribution: measured share per bucket, the
 * calibrated share as a marker where known, and each bucket's multiplier.
 * @param {object} chart
 * @param {string} chart.title
 * @param {number[]} chart.counts drops per bucket
 * @param {number[]} chart.multipliers
 * @param {number[]} [chart.expected] calibrated probability per bucket
 * @returns {string} SVG document
 */
export function distributionChartSvg ({ title, counts, multipliers, expected }) {
  const total = counts.reduce((a, b) => a + b, 0) || 1
  const shares = counts.map((c) => c / total)
  const top = Math.max(...shares, ...(expected ?? [0])) * 1.1 || 1
  const width = 720
  const height = 360
  const left = 50
  const bottom = 300
  const plotHeight = 250
  const barWidth = (width - left - 20) / counts.length
  const y = (share) => bottom - (share / top) * plotHeight
  const parts = []
  parts.push(`<svg xmlns="http://www.w3.org/2000/svg" width="${width}" height="${height}" viewBox="0 0 ${width} ${height}" font-family="sans-serif" font-size="11">`)
  parts.push(`<rect width="${width}" height="${height}" fill="#fff"/>`)
  parts.push(`<text x="${width / 2}" y="20" text-anchor="middle" font-size="14">${escapeXml(title)}</text>`)
  for (let tick = 0; tick <= 4; tick++) {
    const share = (top * tick) / 4
    parts.push(`<line x1="${left}" x2="${width - 20}" y1="${y(share).toFixed(1)}" y2="${y(share).toFixed(1)}" stroke="#eee"/>`)
    parts.push(`<text x="${left - 6}" y="${(y(share) + 4).toFixed(1)}" text-anchor="end">${(share * 100).toFixed(1)}%</text>`)
  }
  shares.forEach((share, i) => {
    const x = left + i * barWidth
    parts.push(`<rect x="${(x + 2).toFixed(1)}" y="${y(share).toFixed(1)}" width="${(barWidth - 4).toFixed(1)}" height="${(bottom - y(share)).toFixed(1)}" fill="#4a7bd0"><title>bucket ${i}: ${(share * 100).toFixed(3)}% (${counts[i]})</title></rect>`)
    if (expected) {
      parts.push(`<line x1="${(x + 2).toFixed(1)}" x2="${(x + barWidth - 2).toFixed(1)}" y1="${y(expected[i]).toFixed(1)}" y2="${y(expected[i]).toFixed(1)}" stroke="#d04a4a" stroke-width="2"/>`)
    }
    parts.push(`<text x="${(x + barWidth / 2).toFixed(1)}" y="${bottom + 14}" text-anchor="middle">${i}</text>`)
    parts.push(`<text x="${(x + barWidth / 2).toFixed(1)}" y="${bottom + 30}" text-anchor="middle" fill="#555">${multipliers[i]}x</text>`)
  })
  parts.push(`<text x="${left}" y="${height - 8}" fill="#4a7bd0">■ measured share</text>`)
  if (expected) parts.push(`<text x="${left + 130}" y="${height - 8}" fill="#d04a4a">— calibrated share</text>`)
  parts.push(`<text x="${width - 20}" y="${height - 8}" text-anchor="end" fill="#555">bucket / multiplier</text>`)
  parts.push('</svg>')
  return parts.join('\n') + '\n'
}

function escapeXml (text) {
  return String(text).replace(/[<>&"]/g, (c) => ({ '<': '&lt;', '>': '&gt;', '&': '&amp;', '"': '&quot;' })[c])
}
