import { el, formatAmount, formatMultiplier, amountTitle, multiplierTitle } from './dom.js'

/** Rows kept in the table; older drops stay in the ledger (GET /api/drops). */
const MAX_ROWS = 100

/**
 * @typedef {object} HistoryEntry one of the player's drops
 * @property {number} dropId @property {string} room @property {number} bet
 * @property {number | null} multiplier @property {number | null} payout
 * @property {boolean | null} verified null while unsettled or unchecked
 * @property {boolean} revealed its server seed has been revealed (verifiable in the fairness panel)
 */

/**
 * The player's drops, newest first, with payout and the browser's
 * verification mark for each.
 */
export class HistoryView {
  /**
   * @param {HTMLTableSectionElement} body the table's tbody
   * @param {(dropId: number) => void} onVerify asks the fairness panel to verify a drop
   * @param {(dropId: number) => void} [onRecall] replays a drop (game recall)
   */
  constructor (body, onVerify, onRecall = () => {}) {
    this.body = body
    this.onVerify = onVerify
    this.onRecall = onRecall
    /** @type {Map<number, { entry: HistoryEntry, row: HTMLTableRowElement }>} */
    this.rows = new Map()
  }

  /** @returns {HistoryEntry[]} newest first */
  get entries () {
    return [...this.rows.values()].map((r) => r.entry).sort((p, q) => q.dropId - p.dropId)
  }

  clear () {
    this.rows.clear()
    this.body.replaceChildren()
  }

  /**
   * Adds or updates a drop's row.
   * @param {number} dropId @param {Partial<HistoryEntry>} changes
   */
  upsert (dropId, changes) {
    let item = this.rows.get(dropId)
    if (!item) {
      const entry = { dropId, room: '', bet: 0, multiplier: null, payout: null, verified: null, revealed: false }
      item = { entry, row: el('tr', { dataset: { dropId: String(dropId) } }) }
      this.rows.set(dropId, item)
      this._insert(item.row, dropId)
      this._trim()
    }
    Object.assign(item.entry, changes)
    this._render(item)
  }

  _insert (row, dropId) {
    // Newest first: before the first row with a smaller id.
    for (const other of this.body.children) {
      if (Number(other.dataset.dropId) < dropId) {
        this.body.insertBefore(row, other)
        return
      }
    }
    this.body.append(row)
  }

  _trim () {
    while (this.rows.size > MAX_ROWS) {
      const oldest = Math.min(...this.rows.keys())
      this.rows.get(oldest).row.remove()
      this.rows.delete(oldest)
    }
  }

  _render ({ entry, row }) {
    const settled = entry.payout !== null
    const net = settled ? entry.payout - entry.bet : null
    const mark = entry.verified === true
      ? el('span', { class: 'mark ok', title: 'bucket, ticks and final state hash match the local simulation', text: '✓', 'aria-label': 'verified' })
      : entry.verified === false
        ? el('span', { class: 'mark bad', title: 'MISMATCH: the local simulation disagrees with the server', text: '⚠ mismatch' })
        : el('span', { class: 'mark wait', text: settled ? '…' : 'in flight' })
    row.className = entry.verified === false ? 'bad' : ''
    row.replaceChildren(
      el('td', { text: `#${entry.dropId}` }),
      el('td', { class: 'room', title: entry.room, text: roomLabel(entry.room) }),
      el('td', { class: 'num', text: formatAmount(entry.bet) }),
      el('td', { class: 'num', text: entry.multiplier === null ? '–' : formatMultiplier(entry.multiplier), title: multiplierTitle(entry.multiplier) }),
      el('td', { class: `num ${net === null ? '' : net >= 0 ? 'win' : 'loss'}`, text: settled ? formatAmount(entry.payout) : '–', title: settled ? amountTitle(entry.payout) : undefined }),
      el('td', { class: 'check' }, mark,
        entry.revealed
          ? el('button', { class: 'small verify-button', type: 'button', text: 'verify', title: 'recompute this drop from the revealed server seed', onclick: () => this.onVerify(entry.dropId) })
          : null,
        settled ? el('button', { class: 'small recall-button', type: 'button', text: '▶', title: 'replay this drop from its seed (game recall)', 'aria-label': `replay drop ${entry.dropId}`, onclick: () => this.onRecall(entry.dropId) }) : null)
    )
  }
}

/** "16-medium" → "16 medium", "16-high.2" → "16 high ·2": whole words (the cell wraps rather than cuts). @param {string} room */
function roomLabel (room) {
  const match = /^(\d+)-(\w+)(?:\.(\d+))?$/.exec(room)
  return match ? `${match[1]} ${match[2]}${match[3] ? ` ·${match[3]}` : ''}` : room
}
