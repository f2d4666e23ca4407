/**
 * What the session panel and the results column count, kept across
 * reloads: this tab's session (sessionStorage, so a reload keeps it and a
 * new tab starts afresh) remembers the newest drop id before it began and
 * before its last reset, and the order the results column showed its
 * results in; on load the page reads the drops after them back from the
 * server's history (GET /api/drops, paged), so both show what they showed
 * before the reload, in the same order.
 */

/** sessionStorage key: { playerId, startAfter, statsAfter, shown? }. */
export const SESSION_MARKS_KEY = 'plinko.sessionMarks'
/** Drops read back at most (pages of 500). */
const MAX_DROPS = 10_000
const PAGE = 500

export class SessionHistory {
  /** @param {{ request: (method: string, path: string) => Promise<any> }} session @param {Storage} [storage] */
  constructor (session, storage = globalThis.sessionStorage) {
    this.session = session
    this.storage = storage
    /** @type {{ playerId: string, startAfter: number, statsAfter: number } | null} */
    this.marks = null
  }

  /**
   * The session's own drops, in the order their results were revealed
   * (oldest first), and from which id the stats
   * count. A tab's first load marks the player's newest drop (nothing
   * before it is this session's). `first` is the newest page the page has
   * read anyway (GET /api/drops?limit=…): older pages are read only when
   * the session goes back further.
   * @param {string} playerId @param {{ drops: any[], limit: number }} first
   * @returns {Promise<{ drops: any[], statsAfter: number }>}
   */
  async load (playerId, first) {
    const stored = this._read()
    if (!stored || stored.playerId !== playerId) {
      const newest = first.drops[0]?.id ?? 0
      this._write({ playerId, startAfter: newest, statsAfter: newest })
      return { drops: [], statsAfter: newest }
    }
    this.marks = stored
    const drops = []
    let page = first.drops
    let limit = first.limit
    for (;;) {
      let done = page.length < limit
      for (const record of page) {
        if (record.id <= stored.startAfter) { done = true; break }
        drops.push(record)
      }
      if (done || drops.length >= MAX_DROPS) break
      limit = PAGE
      page = (await this.session.request('GET', `/api/drops?limit=${PAGE}&before=${page[page.length - 1].id}`)).drops
    }
    return { drops: inShownOrder(drops.reverse(), stored.shown ?? []), statsAfter: stored.statsAfter }
  }

  /**
   * The results column's drops as it shows them now, oldest first: a reload
   * puts them back in this order. A ball can overtake an earlier one of the
   * same player, so the order they were revealed in is not their ids'.
   * @param {number[]} dropIds
   */
  rememberShown (dropIds) {
    if (this.marks) this._write({ ...this.marks, shown: dropIds })
  }

  /** The stats start again after `dropId` (a reset). @param {number} dropId */
  resetStats (dropId) {
    if (this.marks) this._write({ ...this.marks, statsAfter: dropId })
  }

  _read () {
    try {
      const value = JSON.parse(this.storage.getItem(SESSION_MARKS_KEY) ?? 'null')
      if (!value || typeof value.playerId !== 'string' || !Number.isSafeInteger(value.startAfter) || !Number.isSafeInteger(value.statsAfter)) return null
      if (!Array.isArray(value.shown) || !value.shown.every(Number.isSafeInteger)) delete value.shown
      return value
    } catch {
      return null
    }
  }

  _write (marks) {
    this.marks = marks
    this.storage.setItem(SESSION_MARKS_KEY, JSON.stringify(marks))
  }
}

/** A record's landing, as the ledger has it: when its settlement was committed, then its room's tick. */
const landingOrder = (a, b) => (Date.parse(a.settledAt ?? '') || Infinity) - (Date.parse(b.settledAt ?? '') || Infinity) ||
  (a.room === b.room ? (a.startTick + (a.ticks ?? 0)) - (b.startTick + (b.ticks ?? 0)) : 0) || a.id - b.id

/**
 * Records in the order their results were revealed: by landing (settled
 * first, by the commit of their settlement, then by their room's tick), and
 * those the column showed before the reload exactly in the order it showed
 * them, in the places the landing order gives that group.
 * @template {{ id: number, settledAt?: string | null, room?: string, startTick?: number, ticks?: number | null }} R
 * @param {R[]} records @param {number[]} shown oldest first
 * @returns {R[]}
 */
export function inShownOrder (records, shown) {
  const ordered = records.slice().sort(landingOrder)
  const rank = new Map(shown.map((id, i) => [id, i]))
  const places = []
  const group = []
  ordered.forEach((record, i) => { if (rank.has(record.id)) { places.push(i); group.push(record) } })
  group.sort((a, b) => rank.get(a.id) - rank.get(b.id))
  places.forEach((place, i) => { ordered[place] = group[i] })
  return ordered
}
