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

const AMOUNT = new Intl.NumberFormat('en-US', { maximumFractionDigits: 3 })

/**
 * Every play-money amount the pages show (balances, bets, payouts,
 * profits): thousands grouping and up to 3 decimals (milli-credits), no
 * trailing zeros: 1234 → "1,234", 1234.5 → "1,234.5", 0.125 → "0.125".
 * @param {number | null | undefined} value
 */
export function formatAmount (value) {
  if (value === null || value === undefined || !Number.isFinite(value)) return '–'
  // Sums of milli-credit amounts carry binary noise (0.1 + 0.2): round to the milli-credit first; never show "-0".
  const rounded = Math.round(value * 1000) / 1000
  return AMOUNT.format(rounded === 0 ? 0 : rounded)
}

/** A profit with its sign: "+1,234.5", "−20", "0". @param {number} value */
export function formatSigned (value) {
  const text = formatAmount(Math.abs(value))
  const rounded = Math.round(value * 1000) / 1000
  return rounded > 0 ? `+${text}` : rounded < 0 ? `−${text}` : text
}

/** A multiplier as the bucket labels show it: 18×, 5.5×, 0.26×. @param {number} value */
export function formatMultiplier (value) {
  if (value >= 10) return `${Math.round(value * 10) / 10}×`
  if (value >= 1) return `${Math.round(value * 100) / 100}×`
  return `${Math.round(value * 1000) / 1000}×`
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
