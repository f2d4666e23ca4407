/**
 * The session's results read back after a reload: from the newest page the
 * page reads anyway, then older pages (?before=) only while the session
 * goes back further; a first load (or another player) starts the session.
 */
import { describe, it, expect } from 'vitest'
import { SessionHistory } from '../../client/session-history.js'

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
})
