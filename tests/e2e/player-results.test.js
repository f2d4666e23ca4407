/**
 * Issue #24's results and session items, in Chromium against the real
 * server: the recent-results column never clips a chip, at both sizes.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, screenshotBoth, expectNotBlank, DESKTOP, PHONE } from './helpers/player-page.js'
import { RECENT_RESULTS } from '../../client/results-strip.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

/** Plays `count` bets of 1 by auto-bet and waits for every result to be shown. */
async function play (page, count) {
  await page.fill('#bet', '1')
  await page.fill('#auto-count', String(count))
  await page.click('#auto')
  await waitInPage(page, `${count} results shown`, (n) => window.__plinko.auto?.finished && window.__plinko.session.drops === n, count, 120_000)
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
})
