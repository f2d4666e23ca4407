/**
 * The player page's defects of issue #12, each reproduced in Chromium
 * against the real server: ghost balls frozen while the server is silent,
 * revealed seeds lost on reload, "Verify any seeds" that never compared the
 * server seed with its commitment, and labels cut off (history sidebar,
 * room column, multipliers on a phone, the operator's comparison table);
 * plus the layout guarantees: the board's space is reserved before the
 * room is joined (no layout shift) and the header stays one line at 390 px
 * with a balance of 10⁹.
 */
import { describe, it, expect } from 'vitest'
import { createHash } from 'node:crypto'
import { startArenaServer, OPERATOR_TOKEN } from './helpers/arena-server.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, screenshotBoth, expectNotBlank, PHONE, tamperSettledStateHash } from './helpers/player-page.js'

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

const sha256 = (text) => createHash('sha256').update(text, 'utf8').digest('hex')

/** Elements among `selector` whose content is wider than their box (cut off), as text. */
function cutOff (page, selector) {
  return page.evaluate((selector) => [...document.querySelectorAll(selector)]
    .filter((node) => node.scrollWidth > node.clientWidth + 1)
    .map((node) => `${node.tagName} "${node.textContent}" ${node.scrollWidth}>${node.clientWidth}`), selector)
}

/** A table wider than the box that scrolls it. */
function overflowingTable (page, wrapSelector) {
  return page.evaluate((wrapSelector) => {
    const wrap = document.querySelector(wrapSelector)
    return { table: wrap.querySelector('table').getBoundingClientRect().width, wrap: wrap.clientWidth, scroll: wrap.scrollWidth }
  }, wrapSelector)
}

describe('player page defects (issue #12)', () => {
  it('draws no frozen ghost balls while the server is silent, once the real balls have landed', async () => {
    const page = await chromium.newPage()
    // The server "goes down" without closing anything: its frames stop reaching the page.
    let silent = false
    await page.routeWebSocket(/\/ws\?/, (ws) => {
      const upstream = ws.connectToServer()
      upstream.onMessage((message) => { if (!silent) ws.send(message) })
    })
    await page.goto(`${server.base}/?delivery=snapshots`)
    await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
    for (let i = 0; i < 3; i++) await page.click('#drop')
    await waitInPage(page, 'three balls drawn from snapshots', () => window.__plinko.history.length === 3 && window.__plinko.lastFrame.balls >= 3 && window.__plinko.snapshotChecks.positions > 10)
    silent = true

    // The balls fall on along their simulated paths and land; then nothing may stay on the board.
    const { maxUnknown } = await waitInPage(page, 'every ball to land and fade with the server silent', () => {
      window.__maxUnknown = Math.max(window.__maxUnknown ?? 0, window.__plinko.lastFrame.unknown)
      return window.__plinko.ownInFlight === 0 && window.__plinko.lastFrame.balls === 0 && { maxUnknown: window.__maxUnknown }
    })
    expect(maxUnknown).toBe(0)
    // Still nothing a second of frames later (the render clock keeps running past the last snapshot).
    const frames = await page.evaluate(() => window.__plinko.frames)
    await page.evaluate(() => new Promise((resolve) => { let n = 0; const f = () => (++n > 60 ? resolve() : requestAnimationFrame(f)); requestAnimationFrame(f) }))
    const after = await page.evaluate(() => ({ lastFrame: window.__plinko.lastFrame, frames: window.__plinko.frames, status: window.__plinko.status }))
    expect(after.lastFrame).toEqual({ balls: 0, unknown: 0, mine: 0 })
    // Nothing moves, so nothing was redrawn either (a ghost would keep the page drawing).
    expect(after.frames - frames).toBeLessThanOrEqual(2)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('lists revealed seeds after a reload, and "Verify any seeds" compares the seed with its commitment', async () => {
    const page = await openPlayer(chromium, server)
    await page.click('#drop')
    await waitInPage(page, 'a settled drop', () => window.__plinko.history.some((h) => h.payout !== null))
    const [drop] = await page.evaluate(() => window.__plinko.history)
    await page.click('#rotate')
    const reveal = await waitInPage(page, 'the reveal', () => window.__plinko.lastReveal)

    // A reload: the panel lists the revealed seed again, from GET /api/seeds, checked against its hash.
    await page.reload()
    await waitInPage(page, 'the page to join again', () => window.__plinko?.ready === true)
    const seeds = await waitInPage(page, 'the revealed seeds', () => window.__plinko.revealedSeeds?.length > 0 && window.__plinko.revealedSeeds)
    expect(seeds).toEqual([expect.objectContaining({ serverSeed: reveal.previousServerSeed, serverSeedHash: reveal.previousServerSeedHash, nonces: 1, matches: true })])
    const listed = await page.textContent('#revealed-seeds')
    expect(listed).toContain(reveal.previousServerSeed)
    expect(listed).toContain('✓')

    // A wrong server seed: its hash is shown, and it is not the drop's commitment.
    const record = (await page.evaluate((id) => fetch(`/api/drops/${id}`, { headers: { authorization: `Bearer ${JSON.parse(localStorage.getItem('plinko.session')).token}` } }).then((r) => r.json()), drop.dropId))
    expect(record.serverSeedHash).toBe(reveal.previousServerSeedHash)
    await page.click('#fairness details summary')
    const wrong = 'f'.repeat(64)
    await page.fill('#seeds-server', wrong)
    await page.fill('#seeds-client', record.clientSeed)
    await page.fill('#seeds-nonce', String(record.nonce))
    await page.click('#seeds-form button')
    await waitInPage(page, 'the check of the wrong seed', () => window.__plinko.fairnessChecks.length === 1)
    expect(await page.textContent('#verify-computed-hash')).toBe(sha256(wrong))
    expect(await page.textContent('#verify-committed-hash')).toBe(record.serverSeedHash)
    expect(await page.textContent('#verify-hash-verdict')).toContain('DIFFERENT')
    expect(await page.textContent('#verify-verdict')).toContain('DOES NOT MATCH')
    const [wrongCheck] = await page.evaluate(() => window.__plinko.fairnessChecks)
    expect(wrongCheck.checks.commitment).toBe(false)
    expect(wrongCheck.ok).toBe(false)

    // The right one: equal, and the outcome is the drop's.
    await page.fill('#seeds-server', reveal.previousServerSeed)
    await page.click('#seeds-form button')
    await waitInPage(page, 'the check of the right seed', () => window.__plinko.fairnessChecks.length === 2)
    expect(await page.textContent('#verify-computed-hash')).toBe(record.serverSeedHash)
    expect(await page.textContent('#verify-hash-verdict')).toContain('equal')
    expect(await page.textContent('#verify-verdict')).toContain('verified in your browser')
    const right = (await page.evaluate(() => window.__plinko.fairnessChecks))[1]
    expect(right.checks).toEqual({ commitment: true, dropSeed: true, bucket: true, ticks: true, stateHash: true })

    // A committed hash typed in is the one compared.
    await page.fill('#seeds-commitment', '0'.repeat(64))
    await page.click('#seeds-form button')
    await waitInPage(page, 'the check against the typed hash', () => window.__plinko.fairnessChecks.length === 3)
    expect(await page.textContent('#verify-committed-hash')).toBe('0'.repeat(64))
    expect(await page.textContent('#verify-hash-verdict')).toContain('DIFFERENT')

    expectNotBlank(expect, await screenshotBoth(page, 'player-fairness'))
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('cuts no label off: history sidebar and room column, multipliers on a phone, the operator comparison table', async () => {
    // A tampered settlement gives the history its mismatch mark, the longest thing in it.
    const page = await chromium.newPage({ viewport: { width: 1366, height: 800 } })
    await tamperSettledStateHash(page, { once: true })
    await page.goto(`${server.base}/`)
    await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
    await page.selectOption('#risk', 'medium')
    await page.selectOption('#rows', '16')
    await page.selectOption('#risk', 'high')
    await waitInPage(page, 'room 16-high', () => window.__plinko.room === '16-high')
    await page.click('#drop')
    await page.click('#drop')
    await waitInPage(page, 'two settled drops, one flagged', () => window.__plinko.history.filter((h) => h.verified !== null).length === 2)
    expect(await page.textContent('#history')).toContain('16 high')
    expect(await page.textContent('#history .mark.bad')).toContain('mismatch')

    for (const viewport of [{ width: 1366, height: 800 }, PHONE]) {
      await page.setViewportSize(viewport)
      await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))))
      expect(await cutOff(page, '#history td, #history td *'), `history at ${viewport.width}px`).toEqual([])
      const table = await overflowingTable(page, '.history .table-wrap')
      expect(table.scroll, `history table at ${viewport.width}px`).toBeLessThanOrEqual(table.wrap + 1)
      // Every multiplier readable: at least 11 CSS px, within its bucket.
      const labels = await page.evaluate(() => window.__plinko.labels)
      expect(labels).toHaveLength(17)
      for (const label of labels) {
        expect(label.px, `${label.text} at ${viewport.width}px`).toBeGreaterThanOrEqual(11)
        expect(label.width, `${label.text} at ${viewport.width}px`).toBeLessThanOrEqual(label.room + 0.5)
      }
      const header = await cutOff(page, '.topbar, .topbar *')
      expect(header).toEqual([])
    }
    const phoneLabels = await page.evaluate(() => window.__plinko.labels)
    expect(phoneLabels.every((l) => l.upright)).toBe(true)
    expectNotBlank(expect, await screenshotBoth(page, 'player-labels'))
    expect(page.problems).toEqual([])

    // The operator's comparison table at 390 px.
    const token = await page.evaluate(() => JSON.parse(localStorage.getItem('plinko.session')).token)
    const { drops } = (await server.api('GET', '/api/drops', { token })).body
    const audit = await chromium.newPage({ viewport: PHONE, isMobile: true, hasTouch: true })
    await audit.goto(`${server.base}/audit`)
    await audit.evaluate((t) => sessionStorage.setItem('plinko.operatorToken', t), OPERATOR_TOKEN)
    await audit.reload()
    await waitInPage(audit, 'sign-in', () => window.__audit?.signedIn)
    await audit.evaluate((id) => window.__audit.lookupById(id), drops[0].id)
    await waitInPage(audit, 'the comparison table', () => document.querySelector('#record .compare') !== null)
    const compare = await overflowingTable(audit, '#record .table-wrap')
    expect(compare.scroll).toBeLessThanOrEqual(compare.wrap + 1)
    expect(await audit.evaluate(() => document.scrollingElement.scrollWidth <= window.innerWidth)).toBe(true)
    expect(await cutOff(audit, '#record .compare td')).toEqual([])
    expect(audit.problems).toEqual([])
    await audit.context().close()
    await page.context().close()
  })

  it('reserves the board before the room is joined: no layout shift at either size', async () => {
    for (const [viewport, extra] of [[{ width: 1366, height: 800 }, {}], [PHONE, { isMobile: true, hasTouch: true, deviceScaleFactor: 2 }]]) {
      const page = await chromium.newPage({ viewport, ...extra })
      await page.addInitScript(() => {
        window.__shifts = []
        new PerformanceObserver((list) => {
          for (const entry of list.getEntries()) if (!entry.hadRecentInput) window.__shifts.push({ value: entry.value, sources: entry.sources.map((s) => s.node?.className ?? s.node?.nodeName ?? '?') })
        }).observe({ type: 'layout-shift', buffered: true })
      })
      await page.goto(`${server.base}/`)
      await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
      await page.click('#drop')
      await waitInPage(page, 'the result in the strip', () => window.__plinko.recent.length === 1)
      // The same page with no script at all: the stylesheet alone reserves the board's box.
      const bare = await chromium.newPage({ viewport, ...extra, javaScriptEnabled: false })
      await bare.goto(`${server.base}/`)
      const reserved = await bare.evaluate(() => ({ wrap: document.querySelector('.board-wrap').getBoundingClientRect().toJSON(), canvas: document.querySelector('#board').getBoundingClientRect().toJSON() }))
      await bare.context().close()
      const result = await page.evaluate(() => ({
        shifts: window.__shifts,
        wrap: document.querySelector('.board-wrap').getBoundingClientRect().toJSON(),
        canvas: document.querySelector('#board').getBoundingClientRect().toJSON()
      }))
      const total = result.shifts.reduce((sum, s) => sum + s.value, 0)
      expect(total, `layout shift at ${viewport.width}px: ${JSON.stringify(result.shifts)}`).toBeLessThan(0.01)
      // The box reserved before any script runs is the board's, and the canvas fills it.
      expect(Math.abs(reserved.wrap.height - result.wrap.height), `${viewport.width}px`).toBeLessThanOrEqual(2)
      expect(Math.abs(reserved.canvas.height - result.canvas.height), `${viewport.width}px`).toBeLessThanOrEqual(2)
      expect(Math.abs(reserved.canvas.width - result.canvas.width), `${viewport.width}px`).toBeLessThanOrEqual(2)
      expect(Math.abs(result.canvas.height - result.wrap.height)).toBeLessThanOrEqual(2)
      expect(result.canvas.height).toBeGreaterThan(250)
      expect(page.problems).toEqual([])
      await page.context().close()
    }
  })

  it('keeps the header on one line at 390 px with a balance of 10⁹ (milli-credits included)', async () => {
    const rich = await startArenaServer({ tickRate: 60, env: { STARTING_BALANCE: '1000000000' } })
    try {
      const page = await openPlayer(chromium, rich, { viewport: PHONE, isMobile: true, hasTouch: true, deviceScaleFactor: 2 })
      expect(await page.textContent('#balance')).toBe('1,000,000,000')
      // The one formatter of every amount: whole amounts without decimals, others to the cent, thousands grouped
      // (the exact milli-credits on hover). (A string, so the test runner does not rewrite the import.)
      const formatted = await page.evaluate("import('/dom.js').then(({ formatAmount }) => [1000000000.125, 1234.5, 1234.50, 0.1 + 0.2, 7, -2.25, 999999999.999].map(formatAmount))")
      expect(formatted).toEqual(['1,000,000,000.13', '1,234.50', '1,234.50', '0.30', '7', '-2.25', '1,000,000,000.00'])
      const oneLine = async () => page.evaluate(() => {
        const bar = document.querySelector('.topbar')
        const items = [...bar.children].filter((c) => c.getBoundingClientRect().width > 0)
        const tops = items.map((c) => Math.round(c.getBoundingClientRect().top + c.getBoundingClientRect().height / 2))
        return { spread: Math.max(...tops) - Math.min(...tops), right: Math.max(...items.map((c) => c.getBoundingClientRect().right)), width: window.innerWidth, height: bar.getBoundingClientRect().height, scroll: document.scrollingElement.scrollWidth }
      })
      // The widest balance there can be, in every connection state.
      await page.evaluate(() => { document.querySelector('#balance').textContent = '1,000,000,000.125' })
      for (const status of ['open', 'waiting', 'connecting']) {
        await page.evaluate((status) => {
          const pill = document.querySelector('#connection')
          pill.dataset.status = status
          document.querySelector('#connection-text').textContent = status === 'waiting' ? 'reconnecting in 8.0 s' : status
        }, status)
        const line = await oneLine()
        expect(line.spread, status).toBeLessThanOrEqual(4)
        expect(line.right).toBeLessThanOrEqual(line.width)
        expect(line.height).toBeLessThan(60)
        expect(line.scroll).toBeLessThanOrEqual(line.width)
      }
      expect(await cutOff(page, '#balance')).toEqual([])
      expectNotBlank(expect, await screenshotBoth(page, 'player-rich'))
      expect(page.problems).toEqual([])
      await page.context().close()
    } finally {
      await rich.close()
    }
  })
})
