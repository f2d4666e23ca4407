/**
 * Issue #24's layout and look items, in Chromium against the real server:
 * a board that fills the desktop stage; bucket labels and key hints at
 * WCAG AA contrast (4.5:1) and readable sizes (the labels at every width
 * from 320 to 1920 px, never below 11 px nor out of their buckets); floating payouts that never
 * cover the bucket labels; prefers-reduced-motion honoured; connection
 * figures behind a toggle; results and auto-bet's end announced politely.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, activeServerSeed, clientSeedFor, setClientSeed, DESKTOP, PHONE } from './helpers/player-page.js'

let server
let chromium
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

/** WCAG 2 contrast ratio of two CSS colours, as the browser resolves them (runs in the page). */
const CONTRAST = `(a, b) => {
  const probe = document.createElement('i')
  document.body.append(probe)
  const rgb = (css) => { probe.style.color = ''; probe.style.color = css; return getComputedStyle(probe).color.match(/[\\d.]+/g).slice(0, 3).map(Number) }
  const lum = (css) => { const [r, g, b] = rgb(css).map((v) => { v /= 255; return v <= 0.03928 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4 }); return 0.2126 * r + 0.7152 * g + 0.0722 * b }
  const [x, y] = [lum(a), lum(b)].sort((p, q) => q - p)
  probe.remove()
  return (x + 0.05) / (y + 0.05)
}`

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

  it('draws the bucket labels and the key hints at WCAG AA contrast and readable sizes, at both sizes', async () => {
    const page = await openPlayer(chromium, server)
    for (const viewport of [DESKTOP, PHONE]) {
      await page.setViewportSize(viewport)
      await nextFrames(page)
      await nextFrames(page)
      const labels = await page.evaluate(`(() => { const contrast = ${CONTRAST}; return window.__plinko.labels.map((l) => ({ ...l, contrast: contrast(l.color, l.background) })) })()`)
      expect(labels).toHaveLength(17)
      for (const label of labels) {
        expect(label.px, `${label.text} at ${viewport.width} px`).toBeGreaterThanOrEqual(11)
        expect(label.contrast, `${label.text} at ${viewport.width} px`).toBeGreaterThanOrEqual(4.5)
      }
    }
    await page.setViewportSize(DESKTOP)
    await nextFrames(page)
    // Every key hint shown: 12 px or more, 4.5:1 against the first solid background behind it, nothing faded.
    const hints = await page.evaluate(`(() => {
      const contrast = ${CONTRAST}
      return [...document.querySelectorAll('kbd')].filter((k) => k.getClientRects().length > 0).map((k) => {
        let node = k
        let background = null
        let opacity = 1
        for (; node; node = node.parentElement) {
          const style = getComputedStyle(node)
          opacity *= Number(style.opacity)
          if (!background && style.backgroundColor !== 'rgba(0, 0, 0, 0)' && style.backgroundImage === 'none') background = style.backgroundColor
          if (!background && style.backgroundImage !== 'none') background = 'gradient'
        }
        const style = getComputedStyle(k)
        return { text: k.textContent, px: parseFloat(style.fontSize), opacity, background, contrast: background === 'gradient' ? 0 : contrast(style.color, background) }
      })
    })()`)
    expect(hints.length).toBeGreaterThanOrEqual(7)
    for (const hint of hints) {
      expect(hint.px, `"${hint.text}" size`).toBeGreaterThanOrEqual(12)
      expect(hint.opacity, `"${hint.text}" opacity`).toBe(1)
      expect(hint.contrast, `"${hint.text}" contrast on ${hint.background}`).toBeGreaterThanOrEqual(4.5)
    }
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('keeps every bucket label at 11 px or more, inside its bucket, at every width from 320 to 1920 px, on 8 and 16 rows', async () => {
    const page = await openPlayer(chromium, server)
    const wrong = []
    const forms = new Set()
    for (const rows of [16, 8]) {
      for (const risk of ['low', 'medium', 'high']) {
        await page.selectOption('#rows', String(rows))
        await page.selectOption('#risk', risk)
        await waitInPage(page, `room ${rows}-${risk}`, (id) => window.__plinko.room === id, `${rows}-${risk}`)
        for (let width = 320; width <= 1920; width += 40) {
          await page.setViewportSize({ width, height: DESKTOP.height })
          await nextFrames(page)
          await nextFrames(page)
          const labels = await page.evaluate(() => window.__plinko.labels)
          const where = `${rows}-${risk} at ${width} px`
          if (labels.length !== rows + 1) wrong.push(`${where}: ${labels.length} labels`)
          labels.forEach((label, i) => {
            forms.add(label.form)
            const { box, bucket } = label
            if (label.px < 11) wrong.push(`${where}: "${label.text}" drawn at ${label.px.toFixed(2)} px`)
            if (label.width > label.room + 0.5) wrong.push(`${where}: "${label.text}" ${label.width.toFixed(1)} px long in ${label.room.toFixed(1)} px`)
            if (!box || box.left < bucket.left - 0.5 || box.right > bucket.right + 0.5 || box.top < bucket.top - 0.5 || box.bottom > bucket.bottom + 0.5) {
              wrong.push(`${where}: "${label.text}" outside its bucket: ${JSON.stringify(box)} in ${JSON.stringify(bucket)}`)
            }
            const next = labels[i + 1]
            if (next && (!box || !next.box || box.right > next.box.left)) wrong.push(`${where}: "${label.text}" overlaps "${next.text}"`)
          })
          // One form per board: its labels read as one row.
          if (new Set(labels.map((l) => l.form)).size !== 1) wrong.push(`${where}: mixed forms ${labels.map((l) => l.text).join(' ')}`)
        }
      }
    }
    expect(wrong).toEqual([])
    // The sweep went through the shortened forms and the upright labels, not only the wide screens' full ones.
    expect([...forms].sort()).toEqual(['bare', 'full', 'kilo'])
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('floats a payout clear of the bucket labels, at both sizes', async () => {
    const page = await openPlayer(chromium, server)
    const playerId = await page.evaluate(() => window.__plinko.playerId)
    let drops = 0
    for (const viewport of [DESKTOP, PHONE]) {
      await page.setViewportSize(viewport)
      await nextFrames(page)
      // A win of 2× or more floats its payout when its ball lands on screen (a landing the page
      // shows late, on a busy machine, floats nothing): a few tries at most.
      const floatedBefore = await page.evaluate(() => window.__plinko.effects.floaters)
      for (let attempt = 0; attempt < 4; attempt++) {
        const { serverSeed, nextNonce } = await activeServerSeed(server, playerId)
        const win = await clientSeedFor({ serverSeed, nonce: nextNonce, rows: 16, risk: 'medium', wanted: (m) => m >= 2 && m < 10 })
        await setClientSeed(page, win.clientSeed)
        await page.click('#drop')
        await waitInPage(page, 'the result shown', (n) => window.__plinko.session.drops === n, ++drops)
        if (await page.evaluate((n) => window.__plinko.effects.floaters > n, floatedBefore)) break
      }
      await waitInPage(page, 'the payout to float and finish', (n) => window.__plinko.effects.floaters > n && window.__plinko.effects.floating === 0, floatedBefore)
      const clearance = await page.evaluate(() => window.__plinko.effects.floaterClearance)
      expect(clearance, `room between the payout and the buckets at ${viewport.width} px`).toBeGreaterThanOrEqual(0)
    }
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('honours prefers-reduced-motion: no peg glows, pops, floating payouts, bursts, trails or chip animation', async () => {
    const results = {}
    for (const reducedMotion of ['no-preference', 'reduce']) {
      const page = await openPlayer(chromium, server, { reducedMotion })
      const playerId = await page.evaluate(() => window.__plinko.playerId)
      const { serverSeed, nextNonce } = await activeServerSeed(server, playerId)
      // The first drop a win of 2× or more (a floating payout, where motion is allowed); four more after it.
      const win = await clientSeedFor({ serverSeed, nonce: nextNonce, rows: 16, risk: 'medium', wanted: (m) => m >= 2 })
      await setClientSeed(page, win.clientSeed)
      await page.fill('#bet', '1')
      await page.fill('#auto-count', '5')
      await page.click('#auto')
      await waitInPage(page, 'five results shown', () => window.__plinko.auto?.finished && window.__plinko.session.drops === 5)
      results[reducedMotion] = await page.evaluate(() => ({
        effects: window.__plinko.effects,
        chipAnimations: [...document.querySelectorAll('#recent li.chip')].map((li) => getComputedStyle(li).animationName)
      }))
      expect(page.problems).toEqual([])
      await page.context().close()
    }
    const moving = results['no-preference']
    // (Pops and floating payouts come only with landings shown live, which a busy machine may show late: glows and trails always.)
    expect(moving.effects.pegGlows).toBeGreaterThan(0)
    expect(moving.effects.trails).toBeGreaterThan(0)
    expect(moving.chipAnimations).toContain('chip-in')
    const still = results.reduce
    expect(still.effects).toMatchObject({ pegGlows: 0, bucketPops: 0, floaters: 0, bursts: 0, trails: 0 })
    expect(still.chipAnimations.every((name) => name === 'none')).toBe(true)
  })

  it('keeps the connection figures behind a toggle in the footer', async () => {
    const page = await openPlayer(chromium, server)
    await waitInPage(page, 'the footer figures', () => /rtt \d+ ms/.test(document.querySelector('#footer-stats').textContent))
    const visible = () => page.evaluate(() => document.querySelector('footer').innerText)
    expect(await visible()).not.toMatch(/rtt|buffer|snapshot|jitter/)
    expect(await visible()).toContain('Operator audit')
    await page.click('#connection-details summary')
    expect(await visible()).toMatch(/rtt \d+ ms · buffer \d+ ms/)
    expect(await visible()).toMatch(/snapshot positions checked \d+/)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('announces each of the player\'s results and auto-bet\'s end in a polite live region', async () => {
    const page = await openPlayer(chromium, server)
    const region = await page.evaluate(() => { const r = document.querySelector('#announcer'); return { live: r.getAttribute('aria-live'), atomic: r.getAttribute('aria-atomic') } })
    expect(region).toEqual({ live: 'polite', atomic: 'true' })
    await page.fill('#bet', '2')
    await page.click('#drop')
    await waitInPage(page, 'the result shown', () => window.__plinko.session.drops === 1)
    const [drop] = await page.evaluate(() => window.__plinko.history)
    const said = await page.evaluate(() => window.__plinko.announcements)
    expect(said).toHaveLength(1)
    expect(said[0]).toMatch(new RegExp(`^Drop ${drop.dropId}: [\\d.]+×, paid [\\d.,]+ on a bet of 2 `))
    expect(await page.textContent('#announcer')).toBe(said[0])

    await page.fill('#auto-count', '3')
    await page.click('#auto')
    await waitInPage(page, 'the run to finish', () => window.__plinko.auto?.finished && window.__plinko.session.drops === 4)
    await waitInPage(page, 'its end announced', () => window.__plinko.announcements.some((a) => a.includes('Final result')))
    const all = await page.evaluate(() => window.__plinko.announcements)
    expect(all.filter((a) => a.startsWith('Drop '))).toHaveLength(4)
    expect(all.filter((a) => a.includes('Final result'))).toEqual([await page.textContent('#auto-status-text')])
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
