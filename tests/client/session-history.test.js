/**
 * The session's results read back after a reload: from the newest page the
 * page reads anyway, then older pages (?before=) only while the session
 * goes back further; a first load (or another player) starts the session.
 */
import { describe, it, expect } from 'vitest'
import { SessionHistory, SESSION_MARKS_KEY, inShownOrder } from '../../client/session-history.js'

/** The drops route's paging over ids 1..count (newest first), and the requests it served. */
function dropsRoute (count) {
  const requests = []
  return {
    requests,
    async request (method, path) {
      requests.push(path)
      const url = new URL(path, 'http://x')
      const limit = Number(url.searchParams.get('limit'))
      const before = Number(url.searchParams.get('before') ?? Infinity)
      const drops = []
      for (let id = Math.min(count, before - 1); id >= 1 && drops.length < limit; id--) drops.push({ id })
      return { drops }
    }
  }
}

function memoryStorage () {
  const map = new Map()
  return { getItem: (k) => map.get(k) ?? null, setItem: (k, v) => map.set(k, String(v)) }
}

describe('session history', () => {
  it('starts at the newest drop, then reads back every later drop across pages, oldest first', async () => {
    const storage = memoryStorage()
    const first = await dropsRoute(7).request('GET', '/api/drops?limit=50')
    expect(await new SessionHistory(dropsRoute(7), storage).load('p1', { ...first, limit: 50 })).toEqual({ drops: [], statsAfter: 7 })

    // 1,200 drops later: the first page (50) and three more of 500.
    const route = dropsRoute(1207)
    const history = new SessionHistory(route, storage)
    const page = await route.request('GET', '/api/drops?limit=50')
    const { drops, statsAfter } = await history.load('p1', { ...page, limit: 50 })
    expect(drops.map((d) => d.id)).toEqual(Array.from({ length: 1200 }, (_, i) => 8 + i))
    expect(statsAfter).toBe(7)
    expect(route.requests).toEqual(['/api/drops?limit=50', '/api/drops?limit=500&before=1158', '/api/drops?limit=500&before=658', '/api/drops?limit=500&before=158'])

    // A reset: the stats count after it, the drops still come from the session's start.
    history.resetStats(1000)
    const again = await new SessionHistory(route, storage).load('p1', { drops: [], limit: 50 })
    expect(again.statsAfter).toBe(1000)

    // Another player in this tab starts a new session.
    expect(await new SessionHistory(route, storage).load('p2', { ...page, limit: 50 })).toEqual({ drops: [], statsAfter: 1207 })
  })

  it('gives the results back in the order the column showed them, though a later ball overtook an earlier one', async () => {
    // Drop 12 was released after 11 but landed first; both settled in the same commit.
    const at = '2026-12-05T01:00:00.000Z'
    const records = [
      { id: 11, room: '16-medium', startTick: 100, ticks: 190, settledAt: at },
      { id: 12, room: '16-medium', startTick: 110, ticks: 170, settledAt: at },
      { id: 13, room: '16-medium', startTick: 400, ticks: 180, settledAt: '2026-12-05T01:00:05.000Z' }
    ]
    const route = { async request () { return { drops: [] } } }
    const storage = memoryStorage()
    storage.setItem(SESSION_MARKS_KEY, JSON.stringify({ playerId: 'p1', startAfter: 10, statsAfter: 10 }))
    const first = { drops: records.slice().reverse(), limit: 50 }

    // Nothing remembered (a page of an earlier release): the ledger's landing order, the room's tick breaking the tie.
    expect((await new SessionHistory(route, storage).load('p1', first)).drops.map((d) => d.id)).toEqual([12, 11, 13])

    // What the column showed is remembered, and comes back in that order.
    const history = new SessionHistory(route, storage)
    await history.load('p1', first)
    history.rememberShown([11, 12, 13])
    expect((await new SessionHistory(route, storage).load('p1', first)).drops.map((d) => d.id)).toEqual([11, 12, 13])
    expect(JSON.parse(storage.getItem(SESSION_MARKS_KEY))).toEqual({ playerId: 'p1', startAfter: 10, statsAfter: 10, shown: [11, 12, 13] })

    // A remembered order that is not a list of ids is ignored, the rest of the marks kept.
    storage.setItem(SESSION_MARKS_KEY, JSON.stringify({ playerId: 'p1', startAfter: 10, statsAfter: 10, shown: ['x'] }))
    const garbled = await new SessionHistory(route, storage).load('p1', first)
    expect(garbled).toMatchObject({ statsAfter: 10 })
    expect(garbled.drops.map((d) => d.id)).toEqual([12, 11, 13])
  })

  it('puts the remembered results in the places the landing order gives them, the others by landing', () => {
    const record = (id, second) => ({ id, room: 'r', startTick: 0, ticks: 0, settledAt: `2026-12-05T01:00:${String(second).padStart(2, '0')}.000Z` })
    // 1 and 4 were shown before the reload (4 first); 2, 3 and 5 settled while the page was away.
    const records = [record(1, 1), record(2, 2), record(3, 3), record(4, 0), record(5, 5)]
    expect(inShownOrder(records, [4, 1]).map((r) => r.id)).toEqual([4, 1, 2, 3, 5])
    expect(inShownOrder(records, [1, 4]).map((r) => r.id)).toEqual([1, 4, 2, 3, 5])
    expect(inShownOrder(records, []).map((r) => r.id)).toEqual([4, 1, 2, 3, 5])
  })
})
