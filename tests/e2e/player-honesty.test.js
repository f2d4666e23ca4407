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
import { toCredits, toMilli } from '../../protocol/payout.js'
import { formatSigned } from '../../client/dom.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

const dropsSent = (page) => page.evaluate(() => window.__plinko.history.length)

/** Waits for the auto-bet run to stop and its last ball to land; returns the run and the page's settled records of its drops. */
async function finishedRun (page) {
  const run = await waitInPage(page, 'the auto-bet run to finish', () => window.__plinko.auto?.finished && window.__plinko.auto, undefined, 120_000)
  const records = await page.evaluate((ids) => window.__plinko.history.filter((h) => ids.includes(h.dropId)), run.dropIds)
  const profit = toCredits(records.reduce((sum, r) => sum + toMilli(r.payout) - toMilli(r.bet), 0))
  return { run, records, profit, status: await page.textContent('#auto-status-text'), message: await page.textContent('#message') }
}

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

  it('states its stop rule, and ends a stopped run with one final result that counts the balls still falling', async () => {
    const page = await openPlayer(chromium, server)
    expect(await page.textContent('#auto-rule')).toMatch(/stops sending once .* reaches the stop on profit .* balls already falling then still land and count/)
    await page.fill('#bet', '10')
    await page.fill('#auto-count', '200')
    await page.click('#auto-options summary')
    await page.fill('#auto-stop-profit', '5')
    await page.fill('#auto-stop-loss', '30')
    await page.click('#auto')
    const { run, records, profit, status, message } = await finishedRun(page)
    expect(['profit', 'loss']).toContain(run.stopReason)
    // Every ball the run sent has landed and is in its one final figure.
    expect(records).toHaveLength(run.sent)
    expect(records.every((r) => r.payout !== null)).toBe(true)
    expect(run.settled).toBe(run.sent)
    expect(run.profit).toBe(profit)
    // The limit was reached by the landed balls when it stopped sending; after that nothing was sent.
    if (run.stopReason === 'profit') expect(run.stoppedAt.profit).toBeGreaterThanOrEqual(5)
    else expect(run.stoppedAt.profit).toBeLessThanOrEqual(-30)
    expect(run.stoppedAt.sent).toBe(run.sent)
    // One status: why and where it stopped, then the final result (with the late balls, if any); no second figure elsewhere.
    expect(status).toContain(`stopped sending at ${formatSigned(run.stoppedAt.profit)}`)
    expect(status).toContain(`Final result: ${formatSigned(profit)} over ${run.sent} bets`)
    const late = run.sent - run.stoppedAt.settled
    if (late > 0) expect(status).toContain(`counting the ${late} ball${late === 1 ? '' : 's'} still falling when it stopped`)
    expect(message).not.toContain('Auto-bet')
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('can stop before a bet that could take the loss past the stop on loss', async () => {
    const page = await openPlayer(chromium, server)
    await page.fill('#bet', '10')
    await page.fill('#auto-count', '40')
    await page.click('#auto-options summary')
    await page.fill('#auto-stop-loss', '25')
    await page.check('#auto-guard')
    await page.click('#auto')
    const { run, profit, status } = await finishedRun(page)
    // Whatever the balls did, the loss never went past the limit: no bet was sent that could take it there.
    expect(-profit).toBeLessThanOrEqual(25)
    expect(['guard', 'done', 'loss']).toContain(run.stopReason)
    if (run.stopReason === 'guard') {
      expect(-run.stoppedAt.profit + 10).toBeGreaterThan(25)
      expect(status).toContain('could take the loss past the stop on loss of 25')
    }
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
