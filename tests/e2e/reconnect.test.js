/**
 * The player page keeps its session through dropped connections (issue
 * #4): the server cutting the socket, the page's own socket dying, and a
 * full server restart with balls in flight. Each time the page reconnects
 * by itself with backoff, keeps the same player and balance, re-joins its
 * room, and still verifies every drop (those that settled while it was
 * away are checked against the ledger).
 * Servers here run at 180 wall-clock ticks per second: outcomes are the
 * same as at 60, and the page measures the real rate.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

function snapshot (page) {
  return page.evaluate(() => ({
    playerId: window.__plinko.playerId,
    balance: window.__plinko.balance,
    room: window.__plinko.room,
    connects: window.__plinko.connects,
    token: JSON.parse(localStorage.getItem('plinko.session')).token
  }))
}

/** Waits until the page has connected more than `connects` times and joined `room` again. */
function reconnected (page, connects, room) {
  return waitInPage(page, 'the page to reconnect and re-join',
    ([connects, room]) => window.__plinko.connects > connects && window.__plinko.status === 'open' && window.__plinko.room === room,
    [connects, room])
}

async function dropAndVerify (page, count) {
  const before = await page.evaluate(() => window.__plinko.verifications.length)
  for (let i = 0; i < count; i++) await page.click('#drop')
  await waitInPage(page, `${count} more verifications`, (n) => window.__plinko.verifications.length >= n && window.__plinko.pendingVerifications === 0, before + count)
}

describe('reconnecting', () => {
  it('survives the server cutting the connection and the page losing its socket', async () => {
    const page = await chromium.newPage()
    await page.goto(`${server.base}/`)
    await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
    await page.selectOption('#rows', '10')
    await waitInPage(page, 'room 10-medium', () => window.__plinko.room === '10-medium')
    await dropAndVerify(page, 2)
    const first = await snapshot(page)

    // The server end goes away without a close frame.
    expect(server.dropConnections()).toBeGreaterThan(0)
    await reconnected(page, first.connects, '10-medium')
    const second = await snapshot(page)
    expect(second).toMatchObject({ playerId: first.playerId, balance: first.balance, token: first.token })

    // The page's own socket dies.
    await page.evaluate(() => window.__plinko.dropConnection())
    await reconnected(page, second.connects, '10-medium')
    const third = await snapshot(page)
    expect(third).toMatchObject({ playerId: first.playerId, balance: first.balance, token: first.token })

    await dropAndVerify(page, 2)
    const verifications = await page.evaluate(() => window.__plinko.verifications)
    expect(verifications).toHaveLength(4)
    expect(verifications.every((v) => v.verified)).toBe(true)
    const me = await server.api('GET', '/api/me', { token: first.token })
    expect(me.body.playerId).toBe(first.playerId)
    expect(await page.evaluate(() => window.__plinko.balance)).toBe(me.body.balance)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('verifies from the ledger the drops that settled while the page was offline', async () => {
    const page = await chromium.newPage()
    // The page's WebSocket goes through playwright, which can cut the network.
    let networkDown = false
    await page.routeWebSocket(/\/ws\?/, (ws) => {
      if (networkDown) ws.close({ code: 4000, reason: 'network down (test)' })
      else ws.connectToServer()
    })
    await page.goto(`${server.base}/`)
    await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
    const before = await snapshot(page)

    for (let i = 0; i < 3; i++) await page.click('#drop')
    await waitInPage(page, 'three drops announced', () => window.__plinko.history.length >= 3)
    networkDown = true
    server.dropConnections()
    await waitInPage(page, 'the page to go offline', () => window.__plinko.status !== 'open')
    // The balls land and are settled in the ledger while the page cannot hear it.
    const deadline = Date.now() + 60_000
    for (;;) {
      const { drops } = (await server.api('GET', '/api/drops', { token: before.token })).body
      if (drops.length === 3 && drops.every((d) => d.status === 'settled')) break
      if (Date.now() > deadline) throw new Error('drops did not settle')
      await new Promise((resolve) => setTimeout(resolve, 100))
    }
    networkDown = false
    await reconnected(page, before.connects, before.room)

    await waitInPage(page, 'every drop verified', () => window.__plinko.verifications.length >= 3 && window.__plinko.pendingVerifications === 0)
    const verifications = await page.evaluate(() => window.__plinko.verifications)
    expect(verifications).toHaveLength(3)
    expect(verifications.every((v) => v.verified)).toBe(true)
    expect(verifications.filter((v) => v.source === 'ledger').length).toBeGreaterThan(0)
    const after = await snapshot(page)
    expect(after.playerId).toBe(before.playerId)
    const me = await server.api('GET', '/api/me', { token: before.token })
    expect(after.balance).toBe(me.body.balance)
    const history = await page.evaluate(() => window.__plinko.history)
    expect(history.every((h) => h.payout !== null && h.verified === true)).toBe(true)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('survives a server restart with balls in flight', async () => {
    const page = await chromium.newPage()
    await page.goto(`${server.base}/`)
    await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
    await dropAndVerify(page, 1)
    const before = await snapshot(page)

    // Three balls, then a restart while they fall: the old server settles
    // them as it shuts down; the page is offline for a moment.
    for (let i = 0; i < 3; i++) await page.click('#drop')
    await waitInPage(page, 'three drops announced', () => window.__plinko.history.length >= 4)
    await server.restart(() => waitInPage(page, 'the page to notice', () => window.__plinko.status !== 'open'))
    await reconnected(page, before.connects, before.room)

    await waitInPage(page, 'every drop verified', () => window.__plinko.verifications.length >= 4 && window.__plinko.pendingVerifications === 0)
    const after = await snapshot(page)
    expect(after.playerId).toBe(before.playerId)
    expect(after.token).toBe(before.token)
    const verifications = await page.evaluate(() => window.__plinko.verifications)
    expect(verifications.every((v) => v.verified)).toBe(true)
    const me = await server.api('GET', '/api/me', { token: before.token })
    expect(me.body.playerId).toBe(before.playerId)
    expect(after.balance).toBe(me.body.balance)
    const history = await page.evaluate(() => window.__plinko.history)
    expect(history).toHaveLength(4)
    expect(history.every((h) => h.payout !== null && h.verified === true)).toBe(true)

    // And it plays on.
    await dropAndVerify(page, 1)
    // While the server was down the browser itself reports the refused
    // connection attempts; nothing else may appear.
    const unexpected = page.problems.filter((p) => !/WebSocket connection to .* failed|ERR_CONNECTION_REFUSED|Failed to load resource/.test(p))
    expect(unexpected).toEqual([])
    await page.context().close()
  })
})
