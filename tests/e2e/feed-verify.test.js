/**
 * Another player's drop verified on demand (issue #23): in seeds mode the
 * page hears of other players' drops only as compact events, covered by
 * the room's flight hash. A click on such a drop's row in the room feed
 * fetches its public facts (GET /api/public/drops/:id) and checks them
 * with the page's own engine, in Chromium against the real server; a
 * record altered on the way is shown as failing, never as verified.
 */
import { describe, it, expect } from 'vitest'
import { createBoard, simulateDrop } from '../../engine/index.js'
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

describe("verifying another player's drop from the room feed", () => {
  it('checks the drop with the page\'s engine on a click, and shows an altered record as failing', async () => {
    const page = await openPlayer(chromium, server)
    const { settled: [first, second], token } = await otherPlayerDrops(2)
    await waitInPage(page, "the other player's drops in the feed", (ids) => ids.every((id) => window.__plinko.feed.some((e) => e.dropId === id && !e.mine)), [first.dropId, second.dropId])

    await page.click(`#feed tr[data-drop-id="${first.dropId}"]`)
    const verdict = page.locator(`#feed tr[data-check-of="${first.dropId}"]`)
    await verdict.locator('xpath=self::*[contains(@class, "verified") or contains(@class, "failed")]').waitFor()
    const record = (await server.api('GET', `/api/public/drops/${first.dropId}`)).body
    const expected = simulateDrop(createBoard({ rows: record.rows, risk: record.risk, engineVersion: record.engineVersion }), record.dropSeed)
    expect(await verdict.getAttribute('class')).toContain('verified')
    const text = await verdict.textContent()
    expect(text).toContain('✓ Verified in this browser')
    expect(text).toContain(`Bucket ${first.bucket}, ${first.ticks} ticks, state ${first.stateHash}`)
    expect(expected.stateHash).toBe(first.stateHash)
    expect(text).toContain('the outcome of its drop seed (its server seed is not revealed yet)')

    // The other player rotates its seed: the same click now checks the whole chain, from the revealed server seed.
    expect((await server.api('POST', '/api/seeds/rotate', { token })).status).toBe(200)
    await page.click(`#feed tr[data-drop-id="${first.dropId}"]`)
    await waitInPage(page, 'the chain checked', (id) => document.querySelector(`#feed tr[data-check-of="${id}"]`)?.textContent.includes('server seed, its commitment'), first.dropId)
    expect(await verdict.getAttribute('class')).toContain('verified')

    // A record altered on its way to the page: the page's engine disagrees, and says so.
    await page.route(`**/api/public/drops/${second.dropId}`, async (route) => {
      const response = await route.fetch()
      const body = await response.json()
      await route.fulfill({ response, json: { ...body, stateHash: '0'.repeat(16) } })
    })
    await page.focus(`#feed tr[data-drop-id="${second.dropId}"]`)
    await page.keyboard.press('Enter')
    const forged = page.locator(`#feed tr[data-check-of="${second.dropId}"]`)
    await forged.locator('xpath=self::*[contains(@class, "verified") or contains(@class, "failed")]').waitFor()
    expect(await forged.getAttribute('class')).toContain('failed')
    expect(await forged.textContent()).toContain('does NOT verify in this browser (stateHash)')
    expect(await forged.textContent()).toContain(`state ${second.stateHash}`)

    // The player's own rows are not verify buttons (the page verifies its own drops itself).
    expect(await page.locator('#feed tr.mine.checkable').count()).toBe(0)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
