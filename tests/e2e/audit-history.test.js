/**
 * Issue #12, defect 4: the operator page's RTP chart of a quiet room starts
 * from the room's recorded history (GET /api/audit/drops?room=…) instead of
 * empty. A player drops balls and leaves; the room is closed; the operator
 * opens its statistics and sees the measured RTP as it grew over those
 * drops, ending on the figure the stats endpoint reports.
 */
import { describe, it, expect } from 'vitest'
import { rtpStatistics } from '../../engine/index.js'
import { OPERATOR_TOKEN } from './helpers/arena-server.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium, playerWithSettledDrops } from './helpers/testbed.js'
import { screenshotBoth, expectNotBlank } from './helpers/player-page.js'

const ROOM = '10-low'
const DROPS = 16

let server
let chromium

serverAndChromium({ tickRate: 180 }, async (started) => {
  ({ server, chromium } = started)
  await playerWithSettledDrops(server, { room: ROOM, drops: DROPS, bet: 10 })
})

describe('operator page: a quiet room\'s RTP chart', () => {
  it('starts from the room\'s recorded drops', async () => {
    const page = await chromium.newPage({ viewport: { width: 1366, height: 800 } })
    await page.goto(`${server.base}/audit`)
    await page.evaluate((token) => sessionStorage.setItem('plinko.operatorToken', token), OPERATOR_TOKEN)
    await page.reload()
    await waitInPage(page, 'sign-in', () => window.__audit?.signedIn)
    await page.selectOption('#stats-rows', '10')
    await page.selectOption('#stats-risk', 'low')
    await page.click('#stats-form button')
    const samples = await waitInPage(page, 'the chart from history', (n) => window.__audit.historyLoaded === n && window.__audit.stats?.room === '10-low' && window.__audit.rtpSamples, DROPS)

    // One point per recorded drop (fewer than the chart's 60 points), oldest first, ending on the room's figure.
    expect(samples).toHaveLength(DROPS)
    expect(samples.map((s) => s.drops)).toEqual(Array.from({ length: DROPS }, (_, i) => i + 1))
    const stats = await server.audit(`/api/audit/rooms/${ROOM}/stats`)
    const expected = rtpStatistics(stats.bucketCounts, stats.multipliers)
    expect(samples[samples.length - 1].rtp).toBeCloseTo(expected.rtp, 12)
    // The first point is the first drop's multiplier alone.
    const { drops } = await server.audit(`/api/audit/drops?room=${ROOM}&limit=100`)
    const first = drops[drops.length - 1]
    expect(samples[0].rtp).toBeCloseTo(first.multiplier, 12)
    // And the chart draws them: a polyline with a point per sample.
    const points = await page.evaluate(() => [...document.querySelectorAll('#stats svg polyline')].map((p) => p.getAttribute('points').trim().split(/\s+/).length))
    expect(points).toContain(DROPS)
    expectNotBlank(expect, await screenshotBoth(page, 'audit-history'))
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
