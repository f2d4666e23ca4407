/**
 * Issue #24's layout and look items, in Chromium against the real server:
 * a board that fills the desktop stage.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, DESKTOP, PHONE } from './helpers/player-page.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

const nextFrames = (page) => page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))))

describe('player page: layout and look', () => {
  it('draws the board as big as the desktop stage allows, whole in the window; the phone keeps the full width', async () => {
    const page = await openPlayer(chromium, server)
    const boxes = () => page.evaluate(() => ({
      canvas: document.querySelector('#board').getBoundingClientRect().toJSON(),
      stage: document.querySelector('.stage').getBoundingClientRect().toJSON(),
      window: { width: innerWidth, height: innerHeight }
    }))
    const desktop = await boxes()
    // The 16-row board at 1366×800: it used to take 690 of the stage's 884 px (576 px tall).
    expect(desktop.canvas.height).toBeGreaterThanOrEqual(690)
    expect(desktop.canvas.width).toBeGreaterThanOrEqual(0.9 * desktop.stage.width)
    expect(desktop.canvas.width).toBeLessThanOrEqual(desktop.stage.width + 1)
    expect(desktop.canvas.bottom).toBeLessThanOrEqual(desktop.window.height)
    await page.setViewportSize(PHONE)
    await nextFrames(page)
    const phone = await boxes()
    expect(phone.canvas.width).toBeGreaterThanOrEqual(phone.stage.width - 2)
    await page.setViewportSize(DESKTOP)
    await waitInPage(page, 'the board resized back', (h) => document.querySelector('#board').getBoundingClientRect().height === h, desktop.canvas.height)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
