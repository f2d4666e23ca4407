import { el, formatAmount, formatMultiplier, amountTitle, multiplierTitle } from './dom.js'
import { checkPublicDrop, describeCheck } from './public-drop-check.js'

/** Rows kept in the feed. */
const MAX_ROWS = 30
/** A win of this multiple or more is highlighted. */
export const BIG_WIN = 10

/**
 * @typedef {object} FeedEntry
 * @property {number} dropId @property {string} player @property {boolean} mine
 * @property {number} bet @property {number} multiplier @property {number} payout @property {boolean} big
 */

/**
 * The room's drops as they land, newest first: who, bet, multiplier,
 * payout; big wins highlighted. Another player's row verifies that drop
 * in this browser when clicked (or Enter on it): its public facts are
 * fetched and checked with the page's engine (public-drop-check.js), the
 * verdict shown in a row under it.
 */
export class LiveFeed {
  /**
   * @param {HTMLTableSectionElement} body
   * @param {{ check?: (dropId: number) => Promise<import('./public-drop-check.js').PublicDropCheck> }} [options]
   */
  constructor (body, { check = (dropId) => checkPublicDrop(dropId) } = {}) {
    this.body = body
    this.check = check
    /** @type {FeedEntry[]} newest first */
    this.entries = []
    this._ids = new Set()
    /** @type {Map<number, import('./public-drop-check.js').PublicDropCheck>} the checks made, by drop id (for tests and the curious) */
    this.checks = new Map()
    const verifyRow = (event) => {
      const row = event.target.closest?.('tr.checkable')
      if (!row || !this.body.contains(row)) return
      if (event.type === 'keydown' && event.key !== 'Enter' && event.key !== ' ') return
      event.preventDefault()
      this.verify(Number(row.dataset.dropId))
    }
    body.addEventListener('click', verifyRow)
    body.addEventListener('keydown', verifyRow)
  }

  clear () {
    this.entries = []
    this._ids.clear()
    this.body.replaceChildren()
  }

  /**
   * Verifies another player's drop in this browser and shows the verdict
   * under its row. @param {number} dropId
   * @returns {Promise<import('./public-drop-check.js').PublicDropCheck | null>} null: it could not be fetched (said in the row)
   */
  async verify (dropId) {
    const row = this._row(dropId)
    if (!row) return null
    const cell = el('td', { colspan: '4', text: `Verifying drop ${dropId} in this browser…` })
    const shown = el('tr', { class: 'check', role: 'status', dataset: { checkOf: String(dropId) } }, cell)
    this._checkRow(dropId)?.remove()
    row.after(shown)
    try {
      const check = await this.check(dropId)
      this.checks.set(dropId, check)
      shown.classList.add(check.ok ? 'verified' : 'failed')
      cell.textContent = describeCheck(check)
      return check
    } catch (error) {
      shown.classList.add('failed')
      cell.textContent = `Could not fetch drop ${dropId} to verify it: ${error.message}`
      return null
    }
  }

  _row (dropId) {
    return this.body.querySelector(`tr[data-drop-id="${dropId}"]`)
  }

  _checkRow (dropId) {
    return this.body.querySelector(`tr[data-check-of="${dropId}"]`)
  }

  /** @param {Omit<FeedEntry, 'big'>} entry */
  add (entry) {
    if (this._ids.has(entry.dropId)) return
    this._ids.add(entry.dropId)
    const item = { ...entry, big: entry.multiplier >= BIG_WIN }
    this.entries.unshift(item)
    const others = item.mine ? {} : { tabindex: '0', title: 'Verify this drop in your browser' }
    const row = el('tr', { class: [item.mine ? 'mine' : 'checkable', item.big ? 'big' : '', item.payout > item.bet ? 'up' : ''].join(' ').trim(), dataset: { dropId: String(item.dropId) }, ...others },
      el('td', { class: 'who', title: item.player, text: item.mine ? 'you' : shortPlayer(item.player) }),
      el('td', { class: 'num', text: formatAmount(item.bet) }),
      el('td', { class: 'num', text: formatMultiplier(item.multiplier), title: multiplierTitle(item.multiplier) }),
      el('td', { class: `num ${item.payout > item.bet ? 'win' : 'loss'}`, text: formatAmount(item.payout), title: amountTitle(item.payout) }))
    this.body.prepend(row)
    while (this.entries.length > MAX_ROWS) {
      const old = this.entries.pop()
      this._ids.delete(old.dropId)
      this._row(old.dropId)?.remove()
      this._checkRow(old.dropId)?.remove()
    }
  }
}

/** A player id short enough for the feed. @param {string} id */
function shortPlayer (id) {
  return id.length > 8 ? `${id.slice(0, 6)}…` : id
}
