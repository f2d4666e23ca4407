/**
 * A repeat visit (issue #24, item 19), in Chromium against the real
 * server: the player page's versioned files (its bundle and stylesheet)
 * come from the browser's cache with no request at all, not a
 * revalidation answered by a 304; the page itself is still revalidated.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

describe('page cache', () => {
  it('asks nothing for the versioned files on a repeat visit', async () => {
    const page = await chromium.newPage()
    const cdp = await page.context().newCDPSession(page)
    await cdp.send('Network.enable')
    /** @type {Map<string, { url: string, status?: number, fromCache: boolean }>} by request id, this visit's */
    let seen = new Map()
    cdp.on('Network.requestWillBeSent', ({ requestId, request }) => seen.set(requestId, { url: request.url, fromCache: false }))
    cdp.on('Network.requestServedFromCache', ({ requestId }) => { if (seen.has(requestId)) seen.get(requestId).fromCache = true })
    cdp.on('Network.responseReceived', ({ requestId, response }) => {
      const entry = seen.get(requestId)
      if (entry) Object.assign(entry, { status: response.status, fromCache: entry.fromCache || response.fromDiskCache })
    })
    const visit = async () => {
      seen = new Map()
      await page.goto(`${server.base}/`)
      await waitInPage(page, 'the page to join its room', () => window.__plinko?.ready === true)
      return [...seen.values()]
    }
    const first = await visit()
    const versioned = (entries) => entries.filter((e) => /\/(bundle\/player\.js|style\.css)(\?|$)/.test(e.url))
    expect(versioned(first).map((e) => e.status).sort()).toEqual([200, 200])
    const again = await visit()
    const assets = versioned(again)
    expect(assets).toHaveLength(2)
    for (const asset of assets) expect(asset, asset.url).toMatchObject({ fromCache: true })
    expect(again.filter((e) => e.status === 304).map((e) => e.url).filter((url) => !url.endsWith('/'))).toEqual([])
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
