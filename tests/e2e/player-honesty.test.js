/**
 * Issue #24's money and honesty items, in Chromium against the real
 * server: Space bets only when nothing interactive has focus (or the Drop
 * button has it), and auto-bet states its stop rule and ends with one
 * final result that counts the balls still falling when it stopped.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer } from './helpers/player-page.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

const dropsSent = (page) => page.evaluate(() => window.__plinko.history.length)

describe('player page: money and honesty', () => {
  it('drops on Space only with nothing interactive focused or the Drop button focused; a focused control gets its own Space', async () => {
    const page = await openPlayer(chromium, server)
    await page.fill('#bet', '10')

    // Each control, focused, takes Space as its own: no ball drops.
    await page.focus('[data-bet="half"]')
    await page.keyboard.press('Space')
    expect(await page.inputValue('#bet')).toBe('5')

    await page.focus('#mute')
    await page.keyboard.press('Space')
    expect(await page.getAttribute('#mute', 'aria-pressed')).toBe('true')

    await page.focus('#auto-options summary')
    await page.keyboard.press('Space')
    expect(await page.evaluate(() => document.querySelector('#auto-options').open)).toBe(true)

    await page.focus('#session-reset')
    await page.keyboard.press('Space')
    await page.focus('#bet')
    await page.keyboard.press('Space')

    const hashBefore = await page.textContent('#seed-hash')
    await page.focus('#rotate')
    await page.keyboard.press('Space')
    await waitInPage(page, 'the server seed to rotate', (before) => document.querySelector('#seed-hash').textContent !== before, hashBefore)

    // Nothing interactive focused: Space drops. The socket keeps order, so a drop
    // wrongly sent above would have been announced before this one.
    await page.locator('body').click({ position: { x: 5, y: 300 } })
    await page.keyboard.press('Space')
    await waitInPage(page, 'a drop from Space with nothing focused', () => window.__plinko.history.length >= 1)
    expect(await dropsSent(page)).toBe(1)

    // The Drop button focused: Space drops once (not once for the key and once for the button's click).
    await page.focus('#drop')
    await page.keyboard.press('Space')
    await waitInPage(page, 'a drop from Space on the Drop button', () => window.__plinko.history.length === 2)
    await page.click('#drop')
    await waitInPage(page, 'a drop from a click', () => window.__plinko.history.length === 3)
    expect(await dropsSent(page)).toBe(3)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
