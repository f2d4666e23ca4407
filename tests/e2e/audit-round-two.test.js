/**
 * Issue #24's operator page items, in Chromium against the real server:
 * the player list's export, multiplier column, totals and date filter;
 * amounts shown as amounts; round RTP ticks; "Sign out" only when signed
 * in; the replay controls within the first screen at 1366×800; the
 * "Created" column whole on a phone; a wrong token and an unknown drop as
 * messages on the page.
 */
import { describe, it, expect } from 'vitest'
import { OPERATOR_TOKEN } from './helpers/arena-server.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium, playerWithSettledDrops } from './helpers/testbed.js'
import { DESKTOP, PHONE } from './helpers/player-page.js'
import { toCredits, toMilli } from '../../protocol/payout.js'

const ROOM = '8-high'
const DROPS = 6

let server
let chromium
let player
let drops

serverAndChromium({ tickRate: 180 }, async (started) => {
  ({ server, chromium } = started)
  ;({ player, drops } = await playerWithSettledDrops(server, { room: ROOM, drops: DROPS, bet: 10 }))
})

async function signedIn (viewport = DESKTOP) {
  const page = await chromium.newPage({ viewport })
  await page.goto(`${server.base}/audit`)
  await waitInPage(page, 'the audit page', () => window.__audit !== undefined)
  expect(await page.isVisible('#sign-out')).toBe(false)
  await page.fill('#token', OPERATOR_TOKEN)
  await page.click('#sign-in')
  await waitInPage(page, 'sign-in', () => window.__audit.signedIn)
  return page
}

const list = async (page) => {
  await page.fill('#player-id', player.playerId)
  await page.click('#player-form button[type="submit"]')
}

describe('operator page, round two', () => {
  it('lists a player\'s drops with multipliers, totals and a date filter, and exports them', async () => {
    const page = await signedIn()
    expect(await page.isVisible('#sign-out')).toBe(true)
    await list(page)
    await waitInPage(page, 'the list', (n) => document.querySelectorAll('#player-drops tr.clickable').length === n, DROPS)
    const header = await page.$$eval('.player-table thead th', (ths) => ths.map((th) => th.textContent))
    const column = header.indexOf('×') + 1
    expect(column).toBeGreaterThan(0)
    const shown = await page.$$eval(`#player-drops tr td:nth-child(${column})`, (tds) => tds.map((td) => td.textContent))
    expect(shown).toHaveLength(DROPS)
    for (const text of shown) expect(text).toMatch(/^\d+(\.\d{1,2})?×$/)
    const bet = toCredits(drops.reduce((s, d) => s + toMilli(d.bet), 0))
    const paid = toCredits(drops.reduce((s, d) => s + toMilli(d.payout), 0))
    expect(await page.evaluate(() => window.__audit.playerTotals)).toEqual({ drops: DROPS, settled: DROPS, bet, payout: paid, rtp: `${(paid / bet * 100).toFixed(2)}%` })
    expect(await page.textContent('#player-totals')).toContain(`${DROPS} drops`)

    // Dates: a day before the drops finds none; today finds them all.
    const day = (offset) => new Date(Date.now() + offset * 86_400_000).toLocaleDateString('en-CA')
    await page.fill('#player-from', day(-3))
    await page.fill('#player-to', day(-2))
    await list(page)
    await waitInPage(page, 'no drops in those dates', () => /No drops for this player in these dates/.test(document.querySelector('#player-drops').textContent))
    await page.fill('#player-to', day(1))
    await list(page)
    await waitInPage(page, 'the drops again', (n) => document.querySelectorAll('#player-drops tr.clickable').length === n, DROPS)

    // Export: the whole history, as a file.
    const download = page.waitForEvent('download')
    await page.click('#player-export')
    const file = await download
    expect(file.suggestedFilename()).toMatch(/\.ndjson$/)
    expect(await page.evaluate(() => window.__audit.lastExport)).toMatchObject({ player: player.playerId, lines: DROPS })
    expect(await page.textContent('#player-message')).toContain(`Exported ${DROPS} drops`)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('shows a payout as an amount, the multiplier with ×; round RTP ticks; the replay controls on the first screen', async () => {
    const page = await signedIn({ width: 1366, height: 800 })
    const drop = drops.find((d) => !Number.isInteger(d.payout)) ?? drops[0]
    await page.fill('#drop-id', String(drop.id))
    await page.click('#id-form button')
    await waitInPage(page, 'the look-up', () => window.__audit.lookups.length === 1)
    const rows = await page.$$eval('#record table.compare tbody tr', (trs) => trs.map((tr) => [...tr.children].map((td) => td.textContent)))
    const payout = rows.find((r) => r[0] === 'payout')
    const multiplier = rows.find((r) => r[0] === 'multiplier')
    expect(payout[1]).not.toContain('×')
    expect(Number(payout[1].replace(/,/g, ''))).toBe(drop.payout)
    expect(multiplier[1]).toBe(`${drop.multiplier}×`)
    const controls = await page.evaluate(() => document.querySelector('#play').getBoundingClientRect().bottom)
    expect(controls).toBeLessThanOrEqual(800)

    await page.selectOption('#stats-rows', '8')
    await page.selectOption('#stats-risk', 'high')
    await page.click('#stats-form button')
    const rtpTicks = '#stats svg[aria-label^="measured RTP"] .tick-label'
    await waitInPage(page, 'the RTP chart', (selector) => document.querySelectorAll(selector).length >= 2, rtpTicks)
    const ticks = await page.$$eval(rtpTicks, (labels) => labels.map((l) => l.textContent))
    const values = ticks.map((t) => Number(t.replace('%', '')))
    for (const t of ticks) expect(t).toMatch(/^\d+(\.\d{1,2})?%$/)
    const steps = values.slice(1).map((v, i) => Math.round((v - values[i]) * 100) / 100)
    expect(new Set(steps).size).toBe(1)
    // 1, 2 or 5 times a power of ten, whatever the power (a room that paid a big multiplier has RTP ticks of 1,000%)
    const step = Math.abs(steps[0])
    const power = 10 ** Math.floor(Math.log10(step) + 1e-9)
    expect([1, 2, 5, 10].some((m) => Math.abs(step - m * power) < 1e-9 * step)).toBe(true)
    for (const v of values) expect(Math.abs(v / Math.abs(steps[0]) - Math.round(v / Math.abs(steps[0])))).toBeLessThan(1e-6)
    expect(Math.min(...values)).toBeGreaterThanOrEqual(0)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('keeps the "Created" column whole on a phone', async () => {
    const page = await signedIn(PHONE)
    await list(page)
    await waitInPage(page, 'the list', (n) => document.querySelectorAll('#player-drops tr.clickable').length === n, DROPS)
    const fits = () => page.evaluate(() => {
      const wrap = document.querySelector('.player-drops .table-wrap')
      const box = wrap.getBoundingClientRect()
      const cells = [...document.querySelectorAll('#player-drops td.created')].map((td) => td.getBoundingClientRect())
      return { scroll: wrap.scrollWidth - wrap.clientWidth, inside: cells.every((r) => r.left >= box.left - 0.5 && r.right <= box.right + 0.5) }
    })
    expect(await fits()).toEqual({ scroll: 0, inside: true })
    // The drops' outcomes are random: this list may hold only small amounts. Wide ones must fit
    // too (a 1,000× win on a bet of 100 among bets of up to 1,000, an RTP in the thousands); they
    // once did not, when a 29× win here made the RTP in the totals row widen the × column.
    await page.evaluate(() => {
      const cells = document.querySelector('#player-drops tr.clickable').children
      cells[2].textContent = '1,000'
      cells[3].textContent = '1,000×'
      cells[5].textContent = '100,000'
      const totals = document.querySelectorAll('#player-totals th')
      totals[1].textContent = '6,000'
      totals[4].textContent = '100,000'
      totals[5].textContent = '6 settled, RTP 16666.67%'
    })
    expect(await fits()).toEqual({ scroll: 0, inside: true })
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('shows a wrong token and an unknown drop as messages on the page, with a clean console', async () => {
    const page = await chromium.newPage({ viewport: DESKTOP })
    await page.goto(`${server.base}/audit`)
    await waitInPage(page, 'the audit page', () => window.__audit !== undefined)
    await page.fill('#token', 'x'.repeat(32))
    await page.click('#sign-in')
    await waitInPage(page, 'the refusal', () => /not the operator token/.test(document.querySelector('#login-message').textContent))
    await page.fill('#token', OPERATOR_TOKEN)
    await page.click('#sign-in')
    await waitInPage(page, 'sign-in', () => window.__audit.signedIn)
    await page.fill('#drop-id', '999999')
    await page.click('#id-form button')
    await waitInPage(page, 'the message', () => /999999/.test(document.querySelector('#lookup-message').textContent) && document.querySelector('#lookup-message').dataset.kind === 'error')
    expect(await page.textContent('#lookup-message')).toBe('Drop #999999: no drop 999999 is recorded.')
    expect(await page.isVisible('#record .banner')).toBe(false)
    // Neither is a refused request (the token check and the list answer 200): nothing in the console.
    expect(page.problems).toEqual([])
    expect(page.warnings).toEqual([])
    await page.context().close()
  })
})
