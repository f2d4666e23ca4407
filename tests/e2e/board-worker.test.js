/**
 * Where the player page draws its board (client/board-renderer.js): in a
 * worker on an OffscreenCanvas where the browser allows it, and on the
 * main thread when that worker cannot start (its script blocked or
 * missing): the page says so in its console once, the player sees the
 * board and the balls as before, and a drop is played and revealed.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { DESKTOP, canvasStats } from './helpers/player-page.js'

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

/** The board's pixels have the board on them (its background, pegs and buckets: many colours, bright pegs). */
async function expectBoardDrawn (page) {
  const stats = await canvasStats(page)
  expect(stats.width).toBeGreaterThan(0)
  expect(stats.colors).toBeGreaterThan(20)
  expect(stats.bright).toBeGreaterThan(50)
}

describe('player page: the board drawn in a worker, or on the main thread', () => {
  it('draws in the worker where it can, with a clean console', async () => {
    const page = await chromium.newPage({ viewport: DESKTOP })
    await page.goto(server.base)
    await waitInPage(page, 'the page to join its room', () => window.__plinko?.ready === true)
    await waitInPage(page, 'a frame drawn by the worker', () => window.__plinko.frames > 0)
    expect(await page.evaluate(() => window.__plinko.boardDrawnIn)).toBe('worker')
    await expectBoardDrawn(page)
    expect(page.problems).toEqual([])
    expect(page.warnings).toEqual([])
    await page.context().close()
  })

  it('falls back to the main thread when the worker script cannot load, and still plays a drop', async () => {
    const page = await chromium.newPage({ viewport: DESKTOP })
    let blocked = 0
    await page.route('**/bundle/board-worker.js*', (route) => { blocked++; return route.abort() })
    await page.goto(server.base)
    await waitInPage(page, 'the page to join its room', () => window.__plinko?.ready === true)
    await waitInPage(page, 'the board drawn on the main thread', () => window.__plinko.boardDrawnIn === 'main' && window.__plinko.frames > 0)
    expect(blocked).toBeGreaterThan(0)
    // One warning that says what happened; the failed request is the only error line.
    expect(page.warnings.filter((text) => /board worker failed; drawing on the main thread/.test(text))).toHaveLength(1)
    expect(page.problems.filter((line) => !/Failed to load resource|board-worker\.js/.test(line))).toEqual([])
    await expectBoardDrawn(page)
    // The canvas on the page is the main thread's now (the handed-over one was replaced).
    expect(await page.evaluate(() => document.querySelectorAll('canvas#board').length)).toBe(1)

    await page.fill('#bet', '10')
    await page.click('#drop')
    await waitInPage(page, 'the drop revealed', () => window.__plinko.recent.length >= 1)
    await expectBoardDrawn(page)
    await page.context().close()
  })
})
