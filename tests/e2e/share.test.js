/**
 * Share links (issue #24, item 13), in Chromium against the real server:
 * the player makes a link from game recall; anyone opening it watches the
 * drop replayed, sees the player by tag only, and is told when it becomes
 * verifiable; once the player rotates the seed, the same link verifies the
 * whole chain in the viewer's browser. The public route reveals nothing
 * else, and a link with a wrong token finds nothing.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer } from './helpers/player-page.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

const notFoundOnly = (problems) => problems.filter((p) => !/Failed to load resource: the server responded with a status of 404/.test(p))

describe('share links', () => {
  it('shows a shared drop to anyone, replayed, verifiable once revealed, the player by tag only', async () => {
    const page = await openPlayer(chromium, server)
    const playerId = await page.evaluate(() => window.__plinko.playerId)
    await page.fill('#bet', '10')
    await page.click('#drop')
    await waitInPage(page, 'a settled drop', () => window.__plinko.history[0]?.payout != null)
    const dropId = await page.evaluate(() => window.__plinko.history[0].dropId)
    await page.click('#history tr:first-child .recall-button')
    await waitInPage(page, 'the recall', () => window.__plinko.recall?.open)
    await page.click('#recall-share')
    const link = await waitInPage(page, 'the share link', () => window.__plinko.recall.shareLink)
    expect(await page.inputValue('#recall-share-link')).toBe(link)
    const { pathname } = new URL(link)
    expect(pathname).toMatch(new RegExp(`^/share/${dropId}/[0-9a-f]{20}$`))

    // The public reply: the player by tag, no server seed before the reveal, nothing of the session.
    const api = `/api/share/${dropId}/${pathname.split('/')[3]}`
    const before = await server.api('GET', api)
    expect(before.status).toBe(200)
    expect(before.body).toMatchObject({ id: dropId, player: `${playerId.slice(0, 6)}…`, serverSeed: null, verifiable: false, status: 'settled' })
    expect(JSON.stringify(before.body)).not.toContain(playerId)
    expect(Object.keys(before.body)).not.toContain('playerId')

    // A viewer with no session: replayed, not verifiable yet, and says when it will be.
    const viewer = await chromium.newPage()
    await viewer.goto(link)
    await waitInPage(viewer, 'the shared drop', () => window.__share.status === 'shown')
    expect(await viewer.evaluate(() => ({ verified: window.__share.verified, verifiable: window.__share.verifiable }))).toEqual({ verified: null, verifiable: false })
    expect(await viewer.textContent('#share-verdict')).toContain('Not verifiable yet')
    expect(await viewer.textContent('#share-verdict')).toContain('until the player rotates it')
    expect(await viewer.textContent('#share-server-seed')).toContain('secret')
    expect(await viewer.textContent('body')).not.toContain(playerId)
    expect(await viewer.textContent('#share-summary')).toContain(`Player ${playerId.slice(0, 6)}…`)
    await waitInPage(viewer, 'the replay to land', () => window.__share.status === 'shown' && document.querySelector('#share-board').width > 0)
    expect(viewer.problems).toEqual([])

    // The player rotates: the same link now shows the seed and verifies the chain in the viewer's browser.
    await page.keyboard.press('Escape')
    await page.click('#rotate')
    await waitInPage(page, 'the seed revealed', () => window.__plinko.revealedSeeds.length >= 1)
    await viewer.reload()
    await waitInPage(viewer, 'the shared drop again', () => window.__share.status === 'shown')
    expect(await viewer.evaluate(() => ({ verified: window.__share.verified, verifiable: window.__share.verifiable }))).toEqual({ verified: true, verifiable: true })
    expect(await viewer.textContent('#share-verdict')).toContain('✓ Verified in this browser')
    const after = await server.api('GET', api)
    expect(after.body.serverSeed).toMatch(/^[0-9a-f]{64}$/)
    expect(await viewer.textContent('#share-server-seed')).toBe(after.body.serverSeed)
    expect(viewer.problems).toEqual([])

    // Another token, or another id with this token: nothing (the same 404).
    const wrong = pathname.replace(/[0-9a-f]{20}$/, (t) => (t[0] === '0' ? '1' : '0') + t.slice(1))
    for (const path of [wrong.replace('/share/', '/api/share/'), `/api/share/${dropId + 1000}/${pathname.split('/')[3]}`]) {
      const reply = await server.api('GET', path)
      expect(reply.status, path).toBe(404)
      expect(reply.body.code).toBe('E_NOT_FOUND')
    }
    await viewer.goto(`${server.base}${wrong}`)
    await waitInPage(viewer, 'the message', () => window.__share.status === 'error')
    expect(await viewer.textContent('#share-verdict')).toBe('No drop is shared with this link.')
    expect(notFoundOnly(viewer.problems)).toEqual([])
    expect(page.problems).toEqual([])
    await viewer.context().close()
    await page.context().close()
  })
})
