/**
 * Tiny DOM helpers shared by both pages: element building without
 * innerHTML (so nothing the server sends is ever parsed as markup), and
 * number formatting.
 */

/**
 * @param {string} tag
 * @param {Record<string, any>} [attributes] `class`, `text`, `dataset`, on* handlers, or attributes
 * @param {...(Node | string | null | undefined | false)} children
 * @returns {HTMLElement}
 */
export function el (tag, attributes = {}, ...children) {
  const node = document.createElement(tag)
  for (const [name, value] of Object.entries(attributes)) {
    if (value === undefined || value === null || value === false) continue
    if (name === 'class') node.className = value
    else if (name === 'text') node.textContent = value
    else if (name === 'dataset') Object.assign(node.dataset, value)
    else if (name.startsWith('on') && typeof value === 'function') node.addEventListener(name.slice(2), value)
    else node.setAttribute(name, value === true ? '' : String(value))
  }
  for (const child of children) {
    if (child === null || child === undefined || child === false) continue
    node.append(child)
  }
  return node
}

/**
 * Replaces `node`'s children, skipping null/undefined/false (which
 * replaceChildren would turn into text).
 * @param {Element} node @param {...(Node | string | null | undefined | false)} children
 */
export function fill (node, ...children) {
  node.replaceChildren(...children.filter((child) => child !== null && child !== undefined && child !== false))
}

/** @param {string} id @returns {any} the element, or throws: the page's markup is part of the code */
export function byId (id) {
  const node = document.getElementById(id)
  if (!node) throw new Error(`#${id} is missing from the page`)
  return node
}

const WHOLE = new Intl.NumberFormat('en-US', { maximumFractionDigits: 0 })
const CENTS = new Intl.NumberFormat('en-US', { minimumFractionDigits: 2, maximumFractionDigits: 2 })
const EXACT = new Intl.NumberFormat('en-US', { maximumFractionDigits: 3 })

/** Sums of milli-credit amounts carry binary noise (0.1 + 0.2): to the milli-credit, never -0. @param {number} value */
function toMilliCredit (value) {
  const rounded = Math.round(value * 1000) / 1000
  return rounded === 0 ? 0 : rounded
}

/**
 * Every play-money amount the pages show (balances, bets, payouts,
 * profits), as players read money: thousands grouped, whole amounts
 * without decimals and others with two: 1234 → "1,234", 1234.5 →
 * "1,234.50", 100131.515 → "100,131.52". The exact value (milli-credits)
 * is `exactAmount`, shown on hover (`amountTitle`) and in the records.
 * @param {number | null | undefined} value
 */
export function formatAmount (value) {
  if (value === null || value === undefined || !Number.isFinite(value)) return '–'
  const exact = toMilliCredit(value)
  if (Number.isInteger(exact)) return WHOLE.format(exact)
  const cents = Math.round(exact * 100) / 100
  return CENTS.format(cents === 0 ? 0 : cents)
}

/** An amount to the milli-credit, as the ledger keeps it: "100,131.515". @param {number | null | undefined} value */
export function exactAmount (value) {
  if (value === null || value === undefined || !Number.isFinite(value)) return '–'
  return EXACT.format(toMilliCredit(value))
}

/** The hover text of a shown amount: its exact value, when the display rounded it (else undefined). @param {number | null | undefined} value */
export function amountTitle (value, signed = false) {
  const shown = signed ? formatSigned(value) : formatAmount(value)
  const exact = signed ? signedText(value, exactAmount(Math.abs(value))) : exactAmount(value)
  return exact === shown ? undefined : `exactly ${exact}`
}

/** A profit with its sign: "+1,234.50", "−20", "0". @param {number} value */
export function formatSigned (value) {
  return signedText(value, formatAmount(Math.abs(value)))
}

function signedText (value, text) {
  const rounded = toMilliCredit(value)
  return rounded > 0 ? `+${text}` : rounded < 0 ? `−${text}` : text
}

/**
 * Shows an amount in `node`: as players read it, its exact value on hover.
 * @param {HTMLElement} node @param {number | null | undefined} value @param {boolean} [signed]
 */
export function showAmount (node, value, signed = false) {
  node.textContent = signed ? formatSigned(value) : formatAmount(value)
  const title = amountTitle(value, signed)
  if (title) node.title = title
  else node.removeAttribute('title')
}

/**
 * A multiplier as the page shows it, rounded for display (the tables'
 * exact values are the engine's; `exactMultiplier` shows them): 110×,
 * 5.6×, 0.47×, 0.2×.
 * @param {number} value
 */
export function formatMultiplier (value) {
  if (value >= 100) return `${Math.round(value)}×`
  if (value >= 10) return `${Math.round(value * 10) / 10}×`
  return `${Math.round(value * 100) / 100}×`
}

/** A multiplier as the engine's table has it: 0.471×. @param {number} value */
export function exactMultiplier (value) {
  return `${Math.round(value * 1e6) / 1e6}×`
}

/** The hover text of a shown multiplier, when the display rounded it. @param {number | null | undefined} value */
export function multiplierTitle (value) {
  if (value === null || value === undefined) return undefined
  return exactMultiplier(value) === formatMultiplier(value) ? undefined : `exactly ${exactMultiplier(value)}`
}

/** Local date and time with its zone, in the reader's locale (LOCAL_TIME_OPTIONS). */
export const LOCAL_TIME_OPTIONS = Object.freeze({ year: 'numeric', month: 'short', day: 'numeric', hour: '2-digit', minute: '2-digit', second: '2-digit', timeZoneName: 'short' })
const LOCAL_TIME = new Intl.DateTimeFormat(undefined, LOCAL_TIME_OPTIONS)

/**
 * A recorded time (ISO 8601, UTC) in the reader's time zone, e.g.
 * "Dec 1, 2026, 11:27:24 PM EST"; the record keeps the UTC original.
 * @param {string | null | undefined} iso
 */
export function formatLocalTime (iso) {
  if (!iso) return '–'
  const date = new Date(iso)
  return Number.isNaN(date.getTime()) ? iso : LOCAL_TIME.format(date)
}

/** The first and last characters of a long hex string. @param {string | null | undefined} hex */
export function shortHex (hex, keep = 8) {
  if (!hex) return '–'
  return hex.length <= keep * 2 + 1 ? hex : `${hex.slice(0, keep)}…${hex.slice(-keep)}`
}

/** @param {number} ms @returns {Promise<void>} */
export function delay (ms) {
  return new Promise((resolve) => setTimeout(resolve, ms))
}
