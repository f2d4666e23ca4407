/**
 * Issue #24's results and session items, in Chromium against the real
 * server: the recent-results column never clips a chip, at both sizes;
 * the column and the session stats survive a reload (read back from the
 * server's history), a reset included, and a new tab starts afresh;
 * money as players read it (two decimals) with the exact value on hover
 * and in the record, multipliers rounded for display; the session's
 * figures on one line whatever their size; times in the player's zone,
 * the record's UTC kept beside them.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, screenshotBoth, expectNotBlank, activeServerSeed, clientSeedFor, setClientSeed, DESKTOP, PHONE } from './helpers/player-page.js'
import { RECENT_RESULTS } from '../../client/results-strip.js'
import { LOCAL_TIME_OPTIONS } from '../../client/dom.js'

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

  it('shows money with two decimals and the exact amount on hover and in the record; multipliers rounded for display', async () => {
    const page = await openPlayer(chromium, server)
    await page.selectOption('#rows', '8')
    await page.selectOption('#risk', 'high')
    await waitInPage(page, 'the 8-row high-risk room', () => window.__plinko.room === '8-high')
    const playerId = await page.evaluate(() => window.__plinko.playerId)
    const { serverSeed, nextNonce } = await activeServerSeed(server, playerId)
    const pick = await clientSeedFor({ serverSeed, nonce: nextNonce, rows: 8, risk: 'high', wanted: (m) => m === 0.201 })
    await setClientSeed(page, pick.clientSeed)
    await page.fill('#bet', '1')
    await page.click('#drop')
    await waitInPage(page, 'the result shown', () => window.__plinko.session.drops === 1 && window.__plinko.history[0]?.payout !== null)

    const cell = (selector) => page.evaluate((s) => { const n = document.querySelector(s); return { text: n.textContent, title: n.getAttribute('title') } }, selector)
    const row = '#history tr:first-child'
    expect(await cell(`${row} td:nth-child(4)`)).toEqual({ text: '0.2×', title: 'exactly 0.201×' })
    expect(await cell(`${row} td:nth-child(5)`)).toEqual({ text: '0.20', title: 'exactly 0.201' })
    expect(await cell('#feed tr:first-child td:nth-child(4)')).toEqual({ text: '0.20', title: 'exactly 0.201' })
    expect(await cell('#balance')).toEqual({ text: '99,999.20', title: 'exactly 99,999.201' })
    expect(await cell('#stat-profit')).toEqual({ text: '−0.80', title: 'exactly −0.799' })
    expect(await cell('#stat-wagered')).toEqual({ text: '1', title: null })
    expect(await page.textContent('#recent li:first-child')).toBe('0.2×')
    // The board's labels are rounded too: no label has more than two decimals.
    const labels = await page.evaluate(() => window.__plinko.labels.map((l) => l.text))
    expect(labels).toContain('0.22×')
    for (const label of labels) expect(label).toMatch(/^\d+(\.\d{1,2})?×$/)
    // The record keeps the exact values.
    await page.click(`${row} .recall-button`)
    await waitInPage(page, 'the recall', () => window.__plinko.recall?.open)
    expect(await page.textContent('#recall-data')).toContain('1 → 0.201 (0.201×)')
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('keeps every session figure on one line, and the panel its height, with a seven-figure profit at both sizes', async () => {
    const page = await openPlayer(chromium, server)
    const measure = () => page.evaluate(() => {
      const lineHeight = (n) => parseFloat(getComputedStyle(n).lineHeight) || parseFloat(getComputedStyle(n).fontSize) * 1.3
      return {
        panel: document.querySelector('.panel.session').getBoundingClientRect().height,
        figures: [...document.querySelectorAll('.stat-grid strong')].map((n) => ({ id: n.id, text: n.textContent, lines: Math.round(n.getBoundingClientRect().height / lineHeight(n)), cut: n.scrollWidth > n.clientWidth + 1 }))
      }
    })
    const heights = {}
    for (const viewport of [DESKTOP, PHONE]) {
      await page.setViewportSize(viewport)
      heights[viewport.width] = (await measure()).panel
    }
    await page.setViewportSize(DESKTOP)
    // All in at 53× (not the 110× beside it: that would be eight figures), then a bet of 1 that loses cents:
    // a profit of "+5,199,999.31"-like width.
    const playerId = await page.evaluate(() => window.__plinko.playerId)
    const { serverSeed, nextNonce } = await activeServerSeed(server, playerId)
    const big = await clientSeedFor({ serverSeed, nonce: nextNonce, rows: 16, risk: 'medium', wanted: (m) => m >= 50 && m < 100 })
    await setClientSeed(page, big.clientSeed)
    await page.fill('#bet', '100000')
    await page.click('#drop')
    await waitInPage(page, 'the big win shown', () => window.__plinko.session.drops === 1)
    const small = await clientSeedFor({ serverSeed, nonce: nextNonce + 1, rows: 16, risk: 'medium', wanted: (m) => m < 1 })
    await setClientSeed(page, small.clientSeed)
    await page.fill('#bet', '1')
    await page.click('#drop')
    await waitInPage(page, 'the small loss shown', () => window.__plinko.session.drops === 2)
    for (const viewport of [DESKTOP, PHONE]) {
      await page.setViewportSize(viewport)
      await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))))
      const seen = await measure()
      expect(seen.figures.find((f) => f.id === 'stat-profit').text).toMatch(/^\+5,\d{3},\d{3}\.\d{2}$/)
      for (const figure of seen.figures) expect(figure, `${figure.id} at ${viewport.width} px`).toMatchObject({ lines: 1, cut: false })
      expect(seen.panel, `session panel height at ${viewport.width} px`).toBe(heights[viewport.width])
    }
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('shows when a drop was played in the player\'s own time zone, and keeps the recorded UTC time', async () => {
    const page = await openPlayer(chromium, server, { timezoneId: 'America/New_York', locale: 'en-US' })
    await page.click('#drop')
    await waitInPage(page, 'a settled drop', () => window.__plinko.history[0]?.payout != null)
    const dropId = await page.evaluate(() => window.__plinko.history[0].dropId)
    const record = await server.arena.store.getDrop(dropId)
    await page.click('#history tr:first-child .recall-button')
    await waitInPage(page, 'the recall', () => window.__plinko.recall?.open)
    const utc = await page.textContent('#recall-played-utc')
    expect(new Date(utc).getTime()).toBe(new Date(record.createdAt).getTime())
    expect(utc).toMatch(/Z$/)
    const local = new Intl.DateTimeFormat('en-US', { ...LOCAL_TIME_OPTIONS, timeZone: 'America/New_York' }).format(new Date(utc))
    expect(local).toMatch(/E[SD]T$/)
    expect(await page.textContent('#recall-played')).toBe(local)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
