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
  const parts = []
  parts.push(`<svg xmlns="http://www.w3.org/2000/svg" width="${width}" height="${height}" viewBox="0 0 ${width} ${height}" font-family="sans-serif" font-size="11">`)
  parts.push(`<rect width="${width}" height="${height}" fill="#fff"/>`)
  parts.push(`<text x="${width / 2}" y="20" text-anchor="middle" font-size="14">${escapeXml(title)}</text>`)
  for (const share of ticks) {
    parts.push(`<line x1="${left}" x2="${width - 20}" y1="${y(share).toFixed(1)}" y2="${y(share).toFixed(1)}" stroke="#eee"/>`)
    parts.push(`<text x="${left - 6}" y="${(y(share) + 4).toFixed(1)}" text-anchor="end">${tickLabel(share)}</text>`)
  }
  shares.forEach((share, i) => {
    const x = left + i * barWidth
    parts.push(`<rect x="${(x + 2).toFixed(1)}" y="${y(share).toFixed(1)}" width="${(barWidth - 4).toFixed(1)}" height="${(bottom - y(share)).toFixed(1)}" fill="#4a7bd0"><title>bucket ${i}: ${(share * 100).toFixed(4)}% (${counts[i]})</title></rect>`)
    for (const s of series) {
      parts.push(`<line x1="${(x + 2).toFixed(1)}" x2="${(x + barWidth - 2).toFixed(1)}" y1="${y(s.shares[i]).toFixed(1)}" y2="${y(s.shares[i]).toFixed(1)}" stroke="${s.color}" stroke-width="2"><title>${escapeXml(s.label)}: ${(s.shares[i] * 100).toFixed(4)}%</title></line>`)
    }
    parts.push(`<text x="${(x + barWidth / 2).toFixed(1)}" y="${bottom + 14}" text-anchor="middle">${i}</text>`)
    parts.push(`<text x="${(x + barWidth / 2).toFixed(1)}" y="${bottom + 30}" text-anchor="middle" fill="#555">${multipliers[i]}x</text>`)
  })
  let legendX = left
  parts.push(`<text x="${legendX}" y="${height - 8}" fill="#4a7bd0">■ ${escapeXml(barLabel)}</text>`)
  legendX += 30 + barLabel.length * 6
  for (const s of series) {
    parts.push(`<text x="${legendX}" y="${height - 8}" fill="${s.color}">— ${escapeXml(s.label)}</text>`)
    legendX += 30 + s.label.length * 6
  }
  parts.push(`<text x="${width - 20}" y="${height - 8}" text-anchor="end" fill="#555">bucket / multiplier</text>`)
  parts.push('</svg>')
  return parts.join('\n') + '\n'
}

function escapeXml (text) {
  return String(text).replace(/[<>&"]/g, (c) => ({ '<': '&lt;', '>': '&gt;', '&': '&amp;', '"': '&quot;' })[c])
}
