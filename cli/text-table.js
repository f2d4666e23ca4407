/**
 * Plain-text tables and number formats: the `plinko bench` output and the benchmarks' (bench/).
 */

/**
 * @param {{ title: string, align?: 'left' | 'right' }[]} columns
 * @param {string[][]} rows cells already formatted
 * @returns {string}
 */
export function formatTable (columns, rows) {
  const widths = columns.map((c, i) => Math.max(c.title.length, ...rows.map((r) => String(r[i]).length)))
  const line = (cells) => cells
    .map((cell, i) => (columns[i].align === 'left' ? String(cell).padEnd(widths[i]) : String(cell).padStart(widths[i])))
    .join('  ')
    .trimEnd()
  return [line(columns.map((c) => c.title)), widths.map((w) => '-'.repeat(w)).join('  '), ...rows.map(line)].join('\n')
}

/** Integer with thousands separators. @param {number} n */
export function int (n) {
  return Math.round(n).toLocaleString('en-US')
}

/** Fixed decimals with thousands separators. @param {number} n @param {number} [digits] */
export function fixed (n, digits = 1) {
  return n.toLocaleString('en-US', { minimumFractionDigits: digits, maximumFractionDigits: digits })
}

/** A speed ratio, e.g. 23.4×. @param {number} r */
export function ratio (r) {
  return `${fixed(r, r < 10 ? 2 : 1)}×`
}

/** Bytes, with a sign for growth. @param {number} n */
export function bytes (n) {
  const abs = Math.abs(n)
  const text = abs >= 1048576 ? `${fixed(abs / 1048576, 2)} MiB` : abs >= 1024 ? `${fixed(abs / 1024, 1)} KiB` : `${fixed(abs, abs < 10 && abs % 1 !== 0 ? 2 : 0)} B`
  return n < 0 ? `-${text}` : text
}
