import { el, formatAmount, formatMultiplier, amountTitle, multiplierTitle } from './dom.js'
import { checkPublicDrop, describeCheck } from './public-drop-check.js'

/** Rows kept in the feed. */
const MAX_ROWS = 30
/** A win of this multiple or more is highlighted. */
export const BIG_WIN = 10
/**
 * The feed is written at most once in this many ms: a busy room lands
 * some 30 balls a second, and every write lays out and repaints the feed,
 * which at 100 balls in flight cost the page more than its simulation. A
 * landing after a quiet spell is written at once.
 */
export const FEED_WRITE_MS = 250

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
    /** @type {FeedEntry[]} the rows shown, newest first */
    this.entries = []
    /** @type {FeedEntry[]} added, not written yet; oldest first */
    this._pending = []
    /** drop ids shown or pending */
    this._ids = new Set()
    this._writtenAt = -Infinity
    this._scheduled = false
    /** @type {HTMLTableRowElement[]} rows that left the feed, for the next ones */
    this._spare = []
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
    this._pending = []
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

  /**
   * A landing for the feed (once per drop id). The row is written with
   * those added in the same task, at once if the feed was last written
   * FEED_WRITE_MS ago or more, else then (see FEED_WRITE_MS).
   * @param {Omit<FeedEntry, 'big' | 'dropSeed'> & { dropSeed?: string | null }} entry
   */
  add (entry) {
    if (this._ids.has(entry.dropId)) return
    this._ids.add(entry.dropId)
    this._pending.push({ ...entry, dropSeed: entry.dropSeed ?? null, big: entry.multiplier >= BIG_WIN })
    this._schedule()
  }

  /** Entries added and not written yet, oldest first (`entries` are those shown). */
  get pending () {
    return this._pending.length
  }

  _schedule () {
    if (this._scheduled) return
    this._scheduled = true
    const wait = this._writtenAt + FEED_WRITE_MS - performance.now()
    // A microtask: after the task (or the animation frame) that added it, before the page is drawn.
    if (wait <= 0) queueMicrotask(() => this.write())
    else setTimeout(() => this.write(), wait)
  }

  /** Writes the pending entries' rows, newest first, in one insertion; the rows past MAX_ROWS leave first, and are reused for them. */
  write () {
    this._scheduled = false
    const added = this._pending
    if (added.length === 0) return
    this._pending = []
    this._writtenAt = performance.now()
    const shown = []
    for (let i = added.length - 1; i >= 0; i--) {
      if (shown.length < MAX_ROWS) shown.push(added[i])
      else this._ids.delete(added[i].dropId) // never shown: as if it had scrolled out
    }
    while (this.entries.length > 0 && this.entries.length + shown.length > MAX_ROWS) {
      const old = this.entries.pop()
      this._ids.delete(old.dropId)
      const row = this._row(old.dropId)
      if (row) {
        row.remove()
        this._spare.push(row)
      }
      this._checkRow(old.dropId)?.remove()
    }
    const fragment = document.createDocumentFragment()
    for (const item of shown) fragment.append(this._fillRow(this._spare.pop() ?? newRow(), item))
    this.entries = shown.concat(this.entries)
    this.body.prepend(fragment)
  }

  /** Writes `item` into a feed row (new, or one that left the feed). @param {HTMLTableRowElement} row @param {FeedEntry} item */
  _fillRow (row, item) {
    // Another player's drop is checkable with the seed its room announced (the token of its share link).
    const checkable = !item.mine && item.dropSeed !== null
    row.className = [item.mine ? 'mine' : checkable ? 'checkable' : '', item.big ? 'big' : '', item.payout > item.bet ? 'up' : ''].join(' ').trim()
    row.dataset.dropId = String(item.dropId)
    if (checkable) {
      row.setAttribute('tabindex', '0')
      row.title = 'Verify this drop in your browser'
    } else {
      row.removeAttribute('tabindex')
      row.removeAttribute('title')
    }
    const [who, bet, multiplier, payout] = row.cells
    fillCell(who, item.mine ? 'you' : shortPlayer(item.player), item.player)
    fillCell(bet, formatAmount(item.bet))
    fillCell(multiplier, formatMultiplier(item.multiplier), multiplierTitle(item.multiplier))
    payout.className = `num ${item.payout > item.bet ? 'win' : 'loss'}`
    fillCell(payout, formatAmount(item.payout), amountTitle(item.payout))
    return row
  }
}

/** An empty feed row: who, bet, multiplier, payout. */
function newRow () {
  return el('tr', {}, el('td', { class: 'who' }), el('td', { class: 'num' }), el('td', { class: 'num' }), el('td', { class: 'num' }))
}

/** @param {HTMLTableCellElement} cell @param {string} text @param {string} [title] */
function fillCell (cell, text, title) {
  cell.textContent = text
  if (title) cell.title = title
  else cell.removeAttribute('title')
}

/** A player id short enough for the feed. @param {string} id */
function shortPlayer (id) {
  return id.length > 8 ? `${id.slice(0, 6)}…` : id
}
