/**
 * Another player's drop verified on demand (issue #23): in seeds mode the
 * page hears of other players' drops only as compact events, covered by
 * the room's flight hash. A click on such a drop's row in the room feed
 * fetches the drop through its share link (GET /api/share/:id/:token, the
 * token computed in the browser from the drop seed the room announced)
 * and checks it with the page's own engine, in Chromium against the real
 * server; a record altered on the way is shown as failing, never as
 * verified, and so is a drop the server has not with the announced seed.
 * The same in snapshots mode, where the seed comes in `dropped`.
 */
import { describe, it, expect } from 'vitest'
import { createBoard, simulateDrop } from '../../engine/index.js'
import { shareToken } from '../../server/routes/share.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer } from './helpers/player-page.js'
import { GameClient } from '../server/helpers/game-client.js'

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

/** Another player drops `count` balls in the page's room; resolves with their settlements. */
async function otherPlayerDrops (count) {
  const other = (await server.api('POST', '/api/session')).body
  const client = await GameClient.connect(server.wsUrl(other.token))
  client.send({ type: 'join', room: '16-medium' })
  await client.take('joined')
  const settled = []
  for (let i = 0; i < count; i++) {
    client.send({ type: 'drop', bet: 5, ref: `o${i}` })
    const dropped = await client.take((m) => m.ref === `o${i}`)
    settled.push(await client.take((m) => m.type === 'settled' && m.dropId === dropped.dropId, 60_000))
  }
  await client.close()
  return { settled, token: other.token }
}

/** The API requests the page makes, by path. */
function apiRequests (page) {
  const paths = []
  page.on('request', (request) => {
    const { pathname } = new URL(request.url())
    if (pathname.startsWith('/api/')) paths.push(pathname)
  })
  return paths
}

/** Clicks a feed row and waits for its verdict row; resolves with its class and text. */
async function verifyRow (page, dropId) {
  await page.click(`#feed tr[data-drop-id="${dropId}"]`)
  return verdictOf(page, dropId)
}

async function verdictOf (page, dropId) {
  const verdict = page.locator(`#feed tr[data-check-of="${dropId}"]`)
  await verdict.locator('xpath=self::*[contains(@class, "verified") or contains(@class, "failed")]').waitFor()
  return { className: await verdict.getAttribute('class'), text: await verdict.textContent() }
}

/** The stored drop (the operator's view, for the test only) and the share path its seed gives. */
async function storedDrop (dropId) {
  const { drop } = await server.audit(`/api/audit/drops/${dropId}`)
  return { drop, sharePath: `/api/share/${dropId}/${shareToken(drop.dropSeed)}` }
}

describe("verifying another player's drop from the room feed", () => {
  it("checks the drop with the page's engine on a click, through its share link, and shows an altered record or a missing drop as failing", async () => {
    const page = await openPlayer(chromium, server)
    const requests = apiRequests(page)
    expect(await page.evaluate(() => window.__plinko.delivery)).toBe('seeds')
    const { settled: [first, second], token } = await otherPlayerDrops(2)
    await waitInPage(page, "the other player's drops in the feed", (ids) => ids.every((id) => window.__plinko.feed.some((e) => e.dropId === id && !e.mine)), [first.dropId, second.dropId])

    const { drop, sharePath } = await storedDrop(first.dropId)
    // The seed the page's feed holds is the one the room announced (in a drop-events frame), the stored one.
    expect((await page.evaluate((id) => window.__plinko.feed.find((e) => e.dropId === id), first.dropId)).dropSeed).toBe(drop.dropSeed)
    const outcome = await verifyRow(page, first.dropId)
    // The page asked for the share link of that seed (there is no other route to another player's drop).
    expect(requests).toContain(sharePath)
    expect(requests.filter((path) => path.startsWith('/api/public/'))).toEqual([])
    const expected = simulateDrop(createBoard({ rows: drop.rows, risk: drop.risk, engineVersion: drop.engineVersion }), drop.dropSeed)
    expect(outcome.className).toContain('verified')
    expect(outcome.text).toContain('✓ Verified in this browser')
    expect(outcome.text).toContain(`Bucket ${first.bucket}, ${first.ticks} ticks, state ${first.stateHash}`)
    expect(expected.stateHash).toBe(first.stateHash)
    expect(outcome.text).toContain('the outcome of its drop seed (its server seed is not revealed yet)')

    // The other player rotates its seed: the same click now checks the whole chain, from the revealed server seed.
    expect((await server.api('POST', '/api/seeds/rotate', { token })).status).toBe(200)
    await page.click(`#feed tr[data-drop-id="${first.dropId}"]`)
    await waitInPage(page, 'the chain checked', (id) => document.querySelector(`#feed tr[data-check-of="${id}"]`)?.textContent.includes('server seed, its commitment'), first.dropId)
    expect(await page.locator(`#feed tr[data-check-of="${first.dropId}"]`).getAttribute('class')).toContain('verified')

    // A record altered on its way to the page: the page's engine disagrees, and says so.
    await page.route(`**/api/share/${second.dropId}/*`, async (route) => {
      const response = await route.fetch()
      const body = await response.json()
      await route.fulfill({ response, json: { ...body, stateHash: '0'.repeat(16) } })
    })
    await page.focus(`#feed tr[data-drop-id="${second.dropId}"]`)
    await page.keyboard.press('Enter')
    const forged = await verdictOf(page, second.dropId)
    expect(forged.className).toContain('failed')
    expect(forged.text).toContain('does NOT verify in this browser (stateHash)')
    expect(forged.text).toContain(`state ${second.stateHash}`)

    // A server with no drop of that id and the announced seed (its share link is 404): failing, not "could not fetch".
    await page.route(`**/api/share/${first.dropId}/*`, (route) => route.fulfill({ status: 404, json: { code: 'E_NOT_FOUND', message: `no shared drop ${first.dropId} with this link` } }))
    const missing = await verifyRow(page, first.dropId)
    expect(missing.className).toContain('failed')
    expect(missing.text).toBe(`✗ Drop ${first.dropId}: the server has no drop ${first.dropId} with the seed the room announced.`)

    // The player's own rows are not verify buttons (the page verifies its own drops itself).
    expect(await page.locator('#feed tr.mine.checkable').count()).toBe(0)
    // The one problem: the browser's own line for the 404 made above.
    expect(page.problems).toEqual([expect.stringMatching(new RegExp(`Failed to load resource: the server responded with a status of 404 .*/api/share/${first.dropId}/`))])
    await page.context().close()
  })

  it('verifies it the same way in snapshots mode, with the seed of its `dropped`', async () => {
    const page = await openPlayer(chromium, server, { path: '/?delivery=snapshots' })
    const requests = apiRequests(page)
    expect(await page.evaluate(() => window.__plinko.delivery)).toBe('snapshots')
    const { settled: [theirs] } = await otherPlayerDrops(1)
    await waitInPage(page, "the other player's drop in the feed", (id) => window.__plinko.feed.some((e) => e.dropId === id && !e.mine), theirs.dropId)
    const { sharePath } = await storedDrop(theirs.dropId)
    const verdict = await verifyRow(page, theirs.dropId)
    expect(requests).toContain(sharePath)
    expect(verdict.className).toContain('verified')
    expect(verdict.text).toContain(`✓ Verified in this browser: the outcome of its drop seed (its server seed is not revealed yet). Bucket ${theirs.bucket}, ${theirs.ticks} ticks, state ${theirs.stateHash}.`)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
