import { formatMultiplier } from './dom.js'

/**
 * The ways a bucket's multiplier can be written on the board, plainest
 * first; the renderer takes the first whose every label fits its bucket at
 * a readable size (board-renderer.js), and a board's labels all take the
 * same one, so they read as one row:
 *   full   formatMultiplier's: 1000×, 110×, 0.52×
 *   kilo   thousands in k: 1k× (the others as full)
 *   bare   kilo without the sign: 1k, 110, 0.52
 *   tight  bare without a leading zero: .52 (the last resort)
 */
export const LABEL_FORMS = Object.freeze(['full', 'kilo', 'bare', 'tight'])

/** @param {number} multiplier @param {typeof LABEL_FORMS[number]} form */
export function labelText (multiplier, form) {
  const full = formatMultiplier(multiplier)
  if (form === 'full') return full
  const kilo = multiplier >= 1000 ? `${Math.round(multiplier / 100) / 10}k×` : full
  if (form === 'kilo') return kilo
  const bare = kilo.slice(0, -1)
  return form === 'bare' ? bare : bare.replace(/^0\./, '.')
}
