import { el, formatAmount, formatMultiplier, amountTitle, multiplierTitle } from './dom.js'

/** Rows kept in the feed. */
const MAX_ROWS = 30
/** A win of this multiple or more is highlighted. */
export const BIG_WIN = 10

/**
 * @typedef {object} FeedEntry
 * @property {number} dropId @property {string} player @property {boolean} mine
 * @property {number} bet @property {number} multiplier @property {number} payout @property {boolean} big
 */

/** The room's drops as they land, newest first: who, bet, multiplier, payout; big wins highlighted. */
export class LiveFeed {
  /** @param {HTMLTableSectionElement} body */
  constructor (body) {
    this.body = body
    /** @type {FeedEntry[]} newest first */
    this.entries = []
    this._ids = new Set()
  }

  clear () {
    this.entries = []
    this._ids.clear()
    this.body.replaceChildren()
  }

  /** @param {Omit<FeedEntry, 'big'>} entry */
  add (entry) {
    if (this._ids.has(entry.dropId)) return
    this._ids.add(entry.dropId)
    const item = { ...entry, big: entry.multiplier >= BIG_WIN }
    this.entries.unshift(item)
    const row = el('tr', { class: [item.mine ? 'mine' : '', item.big ? 'big' : '', item.payout > item.bet ? 'up' : ''].join(' ').trim(), dataset: { dropId: String(item.dropId) } },
      el('td', { class: 'who', title: item.player, text: item.mine ? 'you' : shortPlayer(item.player) }),
      el('td', { class: 'num', text: formatAmount(item.bet) }),
      el('td', { class: 'num', text: formatMultiplier(item.multiplier), title: multiplierTitle(item.multiplier) }),
      el('td', { class: `num ${item.payout > item.bet ? 'win' : 'loss'}`, text: formatAmount(item.payout), title: amountTitle(item.payout) }))
    this.body.prepend(row)
    while (this.entries.length > MAX_ROWS) {
      const old = this.entries.pop()
      this._ids.delete(old.dropId)
      this.body.lastElementChild?.remove()
    }
  }
}

/** A player id short enough for the feed. @param {string} id */
function shortPlayer (id) {
  return id.length > 8 ? `${id.slice(0, 6)}…` : id
}
