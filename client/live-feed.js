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
 * @property {string | null} dropSeed the seed its room announced (null: the page never had it, and cannot verify it)
 */

/**
 * The room's drops as they land, newest first: who, bet, multiplier,
 * payout; big wins highlighted. Another player's row verifies that drop
 * in this browser when clicked (or Enter on it): the drop is fetched
 * through its share link, whose token comes from the seed the room
 * announced, and checked with the page's engine (public-drop-check.js),
 * the verdict shown in a row under it.
 */
export class LiveFeed {
  /**
   * @param {HTMLTableSectionElement} body
   * @param {{ check?: (drop: { dropId: number, dropSeed: string }) => Promise<import('./public-drop-check.js').PublicDropCheck> }} [options]
   */
  constructor (body, { check = (drop) => checkPublicDrop(drop) } = {}) {
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
   * @returns {Promise<import('./public-drop-check.js').PublicDropCheck | null>}
   *   null: no such row, no announced seed to check it with, or it could not be fetched (said in the row)
   */
  async verify (dropId) {
    const row = this._row(dropId)
    const entry = this.entries.find((e) => e.dropId === dropId)
    if (!row || !entry?.dropSeed) return null
    const cell = el('td', { colspan: '4', text: `Verifying drop ${dropId} in this browser…` })
    const shown = el('tr', { class: 'check', role: 'status', dataset: { checkOf: String(dropId) } }, cell)
    this._checkRow(dropId)?.remove()
    row.after(shown)
    try {
      const check = await this.check({ dropId, dropSeed: entry.dropSeed })
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

  /** @param {Omit<FeedEntry, 'big' | 'dropSeed'> & { dropSeed?: string | null }} entry */
  add (entry) {
    if (this._ids.has(entry.dropId)) return
    this._ids.add(entry.dropId)
    const item = { ...entry, dropSeed: entry.dropSeed ?? null, big: entry.multiplier >= BIG_WIN }
    this.entries.unshift(item)
    // Another player's drop is checkable with the seed its room announced (the token of its share link).
    const checkable = !item.mine && item.dropSeed !== null
    const others = checkable ? { tabindex: '0', title: 'Verify this drop in your browser' } : {}
    const row = el('tr', { class: [item.mine ? 'mine' : checkable ? 'checkable' : '', item.big ? 'big' : '', item.payout > item.bet ? 'up' : ''].join(' ').trim(), dataset: { dropId: String(item.dropId) }, ...others },
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
