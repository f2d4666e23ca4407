/**
 * What the session panel and the results column count, kept across
 * reloads: this tab's session (sessionStorage, so a reload keeps it and a
 * new tab starts afresh) remembers the newest drop id before it began and
 * before its last reset; on load the page reads the drops after them back
 * from the server's history (GET /api/drops, paged), so both show what
 * they showed before the reload.
 */

/** sessionStorage key: { playerId, startAfter, statsAfter }. */
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
   * The session's own drops, oldest first, and from which id the stats
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
    return { drops: drops.reverse(), statsAfter: stored.statsAfter }
  }

  /** The stats start again after `dropId` (a reset). @param {number} dropId */
  resetStats (dropId) {
    if (this.marks) this._write({ ...this.marks, statsAfter: dropId })
  }

  _read () {
    try {
      const value = JSON.parse(this.storage.getItem(SESSION_MARKS_KEY) ?? 'null')
      return value && typeof value.playerId === 'string' && Number.isSafeInteger(value.startAfter) && Number.isSafeInteger(value.statsAfter) ? value : null
    } catch {
      return null
    }
  }

  _write (marks) {
    this.marks = marks
    this.storage.setItem(SESSION_MARKS_KEY, JSON.stringify(marks))
  }
}
