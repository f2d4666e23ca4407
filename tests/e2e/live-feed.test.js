/**
 * The room feed under a busy room, in Chromium: many landings in one
 * frame are written in one go, each once, newest first, at most 30 rows,
 * the rows that leave reused for new ones with nothing of their old drop
 * left on them; landings soon after a write wait for the next one
 * (FEED_WRITE_MS), and a landing after a quiet spell is written before
 * the page is next drawn.
 */
import { describe, it, expect } from 'vitest'
import { serverAndChromium } from './helpers/testbed.js'

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

/** A blank page of the server's with the feed module loaded: window.feed on a table's body. */
async function openFeed () {
  const page = await chromium.newPage()
  await page.goto(`${server.base}/share.html`)
  // (A string, so the test runner does not rewrite the import.)
  await page.evaluate(`import('/live-feed.js').then(({ LiveFeed, FEED_WRITE_MS }) => {
    const table = document.createElement('table')
    const body = document.createElement('tbody')
    table.append(body)
    document.body.append(table)
    window.feed = new LiveFeed(body, { check: async () => ({ ok: true }) })
    window.FEED_WRITE_MS = FEED_WRITE_MS
    window.rows = () => [...body.rows].map((row) => ({
      id: Number(row.dataset.dropId), className: row.className, tabindex: row.getAttribute('tabindex'), title: row.getAttribute('title'),
      cells: [...row.cells].map((cell) => ({ text: cell.textContent, title: cell.getAttribute('title'), className: cell.className }))
    }))
    window.entry = (dropId, mine = dropId % 3 === 0) => ({ dropId, player: mine ? 'me' : 'player-' + dropId, mine, bet: 1, multiplier: dropId % 5 === 0 ? 26 : 0.5, payout: dropId % 5 === 0 ? 26 : 0.5, dropSeed: mine ? null : 'seed-' + dropId })
  })`)
  return page
}

describe('the room feed', () => {
  it('writes a frame full of landings once each, newest first, at most 30 rows, reusing the rows that leave', async () => {
    const page = await openFeed()
    // A lone landing after a quiet spell: written before the page is next drawn (a microtask after this task).
    const lone = await page.evaluate(() => new Promise((resolve) => {
      window.feed.add(window.entry(1))
      const pendingInTask = window.feed.pending
      requestAnimationFrame(() => resolve({ pendingInTask, rows: window.rows().map((r) => r.id) }))
    }))
    expect(lone).toEqual({ pendingInTask: 1, rows: [1] })

    // 45 landings in one task (and some named twice): none written until the next write is due, then all at once.
    const burst = await page.evaluate(() => {
      const addedAt = performance.now()
      for (let id = 2; id <= 46; id++) window.feed.add(window.entry(id))
      for (let id = 40; id <= 46; id++) window.feed.add(window.entry(id))
      const before = window.rows().length
      return new Promise((resolve) => {
        const observer = new MutationObserver(() => {
          observer.disconnect()
          resolve({ before, waited: performance.now() - addedAt, writeMs: window.FEED_WRITE_MS })
        })
        observer.observe(document.querySelector('tbody'), { childList: true })
      })
    })
    expect(burst.before).toBe(1)
    expect(burst.waited).toBeGreaterThan(burst.writeMs / 2)
    const { rows, entries, pending } = await page.evaluate(() => ({ rows: window.rows(), entries: window.feed.entries.map((e) => e.dropId), pending: window.feed.pending }))
    const newest = Array.from({ length: 30 }, (_, i) => 46 - i)
    expect(pending).toBe(0)
    expect(entries).toEqual(newest)
    expect(rows.map((r) => r.id)).toEqual(newest)
    for (const row of rows) expect(row).toEqual(expectedRow(row.id))

    // Another burst: the rows leaving are reused (no more rows than 30, each the new drop's only).
    const reused = await page.evaluate(() => new Promise((resolve) => {
      const body = document.querySelector('tbody')
      const old = new Set(body.rows)
      for (let id = 47; id <= 56; id++) window.feed.add(window.entry(id))
      const observer = new MutationObserver(() => {
        observer.disconnect()
        resolve({ rows: window.rows(), recycled: [...body.rows].slice(0, 10).filter((row) => old.has(row)).length })
      })
      observer.observe(body, { childList: true })
    }))
    expect(reused.recycled).toBe(10)
    expect(reused.rows.map((r) => r.id)).toEqual(Array.from({ length: 30 }, (_, i) => 56 - i))
    for (const row of reused.rows) expect(row).toEqual(expectedRow(row.id))
    // A drop shown is not added again.
    expect(await page.evaluate(() => { window.feed.add(window.entry(56)); return window.feed.pending })).toBe(0)
    await page.close()
  })
})

/** The row page.evaluate's window.entry(id) gets. */
function expectedRow (id) {
  const mine = id % 3 === 0
  const big = id % 5 === 0
  const checkable = !mine
  return {
    id,
    className: [mine ? 'mine' : 'checkable', big ? 'big' : '', big ? 'up' : ''].join(' ').trim(),
    tabindex: checkable ? '0' : null,
    title: checkable ? 'Verify this drop in your browser' : null,
    cells: [
      { text: mine ? 'you' : id < 10 ? `player-${id}` : 'player…', title: mine ? 'me' : `player-${id}`, className: 'who' },
      { text: '1', title: null, className: 'num' },
      { text: big ? '26×' : '0.5×', title: null, className: 'num' },
      { text: big ? '26' : '0.50', title: big ? null : 'exactly 0.5', className: `num ${big ? 'win' : 'loss'}` }
    ]
  }
}
