/**
 * Issue #24's results and session items, in Chromium against the real
 * server: the recent-results column never clips a chip, at both sizes;
 * the column and the session stats survive a reload (read back from the
 * server's history), a reset included, and a new tab starts afresh.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, screenshotBoth, expectNotBlank, DESKTOP, PHONE } from './helpers/player-page.js'
import { RECENT_RESULTS } from '../../client/results-strip.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

/** Plays `count` bets of 1 by auto-bet and waits for every result to be shown (`drops` in the session stats then). */
async function play (page, count, drops = count) {
  await page.fill('#bet', '1')
  await page.fill('#auto-count', String(count))
  await page.click('#auto')
  await waitInPage(page, `${count} results shown`, (n) => window.__plinko.auto?.finished && window.__plinko.session.drops === n, drops, 120_000)
}

/** What the strip and the session panel show. */
function shown (page) {
  return page.evaluate(() => ({
    recent: window.__plinko.recent.map((r) => [r.dropId, r.multiplier, r.color]),
    session: window.__plinko.session,
    text: ['#stat-wagered', '#stat-profit', '#stat-drops', '#stat-best'].map((s) => document.querySelector(s).textContent),
    chips: [...document.querySelectorAll('#recent li')].map((li) => li.textContent)
  }))
}

/** Each chip's box against the strip's: shown whole, or not at all. */
function chipBoxes (page) {
  return page.evaluate(() => {
    const strip = document.querySelector('#recent').getBoundingClientRect()
    return [...document.querySelectorAll('#recent li.chip')].map((li) => {
      const r = li.getBoundingClientRect()
      const inside = r.left >= strip.left - 0.5 && r.right <= strip.right + 0.5 && r.top >= strip.top - 0.5 && r.bottom <= strip.bottom + 0.5
      const outside = r.right <= strip.left || r.left >= strip.right || r.bottom <= strip.top || r.top >= strip.bottom
      return { top: r.top, bottom: r.bottom, left: r.left, inside, outside, opacity: Number(getComputedStyle(li).opacity) }
    })
  })
}

describe('player page: results and session', () => {
  it('shows the recent results as a fading column that never clips a chip, at both sizes', async () => {
    const page = await openPlayer(chromium, server)
    await play(page, RECENT_RESULTS + 2)
    for (const viewport of [DESKTOP, PHONE]) {
      await page.setViewportSize(viewport)
      // The board is resized on the frame after a resize; the newest chip's entrance runs out.
      await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))))
      await page.evaluate(() => Promise.all(document.getAnimations().map((a) => a.finished)))
      const chips = await chipBoxes(page)
      expect(chips).toHaveLength(RECENT_RESULTS)
      // Each chip is shown whole or not at all.
      for (const [i, chip] of chips.entries()) expect(chip.inside || chip.outside, `chip ${i} at ${viewport.width} px clipped`).toBe(true)
      const shown = chips.filter((c) => c.inside)
      expect(shown.length, `chips shown at ${viewport.width} px`).toBeGreaterThanOrEqual(5)
      // Newest on top, one under the other, older ones fainter.
      for (let i = 1; i < shown.length; i++) {
        expect(shown[i].top).toBeGreaterThanOrEqual(shown[i - 1].bottom)
        expect(shown[i].left).toBe(shown[0].left)
        expect(shown[i].opacity).toBeLessThanOrEqual(shown[i - 1].opacity)
      }
      expect(shown.at(-1).opacity).toBeLessThan(shown[0].opacity)
    }
    expectNotBlank(expect, await screenshotBoth(page, 'player-results'))
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('keeps the results column and the session stats across reloads, from the server\'s history; a reset too; a new tab starts afresh', async () => {
    const page = await openPlayer(chromium, server)
    await play(page, 4)
    const before = await shown(page)
    expect(before.recent).toHaveLength(4)
    await page.reload()
    await waitInPage(page, 'the page to join again', () => window.__plinko?.ready === true)
    expect(await shown(page)).toEqual(before)

    // A reset counts from there, across a reload too; the column keeps the session's results.
    await page.click('#session-reset')
    await play(page, 2)
    const afterReset = await shown(page)
    expect(afterReset.session).toMatchObject({ drops: 2, wagered: 2 })
    expect(afterReset.recent).toHaveLength(6)
    await page.reload()
    await waitInPage(page, 'the page to join again', () => window.__plinko?.ready === true)
    expect(await shown(page)).toEqual(afterReset)
    expect(page.problems).toEqual([])

    // Another tab of the same player is another session.
    const tab = await page.context().newPage()
    await tab.goto(`${server.base}/`)
    await waitInPage(tab, 'the new tab to join', () => window.__plinko?.ready === true)
    expect(await tab.evaluate(() => window.__plinko.playerId)).toBe(await page.evaluate(() => window.__plinko.playerId))
    expect(await tab.evaluate(() => ({ recent: window.__plinko.recent.length, drops: window.__plinko.session.drops }))).toEqual({ recent: 0, drops: 0 })
    await page.context().close()
  })
})
