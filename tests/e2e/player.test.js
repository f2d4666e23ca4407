/**
 * The player page in real Chromium against the real server (issue #4):
 * drops balls with the keyboard, the button and auto-drop, waits for every
 * settlement, and checks that the page verified every drop — its own
 * simulation's bucket, ticks and final state hash equal what the server
 * announced, what another client in the room received, and what the
 * ledger stored — that the canvas shows the board, and that the console
 * stayed clean; and that a tampered outcome raises a loud warning. Also the fairness panel (client seed, rotation,
 * verification of a revealed drop in the browser), room changes and a
 * phone-sized screen.
 */
import { describe, it, expect } from 'vitest'
import { mkdirSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { canvasStats, tamperSettledStateHash } from './helpers/player-page.js'
import { imageStats } from './helpers/png.js'
import { GameClient } from '../server/helpers/game-client.js'

const SCREENSHOTS = join(tmpdir(), 'plinko-e2e-screenshots')

let server
let chromium

serverAndChromium({ tickRate: 60 }, async (started) => {
  ({ server, chromium } = started)
  mkdirSync(SCREENSHOTS, { recursive: true })
})

/** Saves a screenshot and returns what is on it. */
async function screenshot (page, name, options = {}) {
  const png = await page.screenshot(options)
  const file = join(SCREENSHOTS, `${name}.png`)
  writeFileSync(file, png)
  console.info(`[e2e] screenshot ${file}`)
  return imageStats(png)
}

async function openPlayer (options = {}) {
  const page = await chromium.newPage(options)
  await page.goto(`${server.base}/`)
  await waitInPage(page, 'the page to join its room', () => window.__plinko?.ready === true)
  return page
}

function sessionToken (page) {
  return page.evaluate(() => JSON.parse(localStorage.getItem('plinko.session')).token)
}

describe('player page in Chromium', () => {
  it('renders the room, verifies every drop against the server and the ledger, with a clean console', async () => {
    const page = await openPlayer({ viewport: { width: 1280, height: 900 } })
    const room = await page.evaluate(() => window.__plinko.room)
    expect(room).toBe('16-medium')

    // Another player in the same room records what the server broadcast.
    const observerSession = (await server.api('POST', '/api/session')).body
    const observer = await GameClient.connect(server.wsUrl(observerSession.token))
    observer.send({ type: 'join', room })
    await observer.take('joined')

    const startBalance = await page.evaluate(() => window.__plinko.balance)
    await page.fill('#bet', '25')
    await page.locator('body').click({ position: { x: 5, y: 5 } })
    for (let i = 0; i < 3; i++) await page.keyboard.press('Space')
    await page.click('#drop')
    await page.click('#drop')
    await page.fill('#auto-count', '5')
    await page.click('#auto')
    const dropCount = 10

    // Mid-flight: balls on the board.
    await waitInPage(page, 'balls in flight', () => window.__plinko.history.length >= 3)
    const flying = await screenshot(page, 'player-in-flight')
    expect(flying.distinctColors).toBeGreaterThan(50)

    await waitInPage(page, `${dropCount} verifications`, (n) => window.__plinko.verifications.length >= n, dropCount, 120_000)
    await waitInPage(page, 'the history to settle', (n) => window.__plinko.history.filter((h) => h.payout !== null).length >= n, dropCount)
    const result = await page.evaluate(() => ({
      verifications: window.__plinko.verifications,
      history: window.__plinko.history,
      balance: window.__plinko.balance,
      playerId: window.__plinko.playerId,
      delivery: window.__plinko.delivery,
      seeds: window.__plinko.seeds.room,
      timeline: window.__plinko.timeline,
      warnings: window.__plinko.warnings,
      summary: document.querySelector('#verify-summary').textContent,
      marks: [...document.querySelectorAll('#history .mark')].map((m) => m.className)
    }))
    console.info(`[e2e] clock ${JSON.stringify(result.timeline)}, seeds room ${JSON.stringify(result.seeds)}`)

    const mine = result.verifications.filter((v) => v.mine)
    expect(mine).toHaveLength(dropCount)
    for (const v of result.verifications) {
      expect(v, `drop ${v.dropId}`).toMatchObject({ verified: true, source: 'live' })
      expect(v.localBucket).toBe(v.serverBucket)
      expect(v.localTicks).toBe(v.serverTicks)
      expect(v.localStateHash).toMatch(/^[0-9a-f]{16}$/)
      expect(v.localStateHash).toBe(v.serverStateHash)
    }
    expect(result.warnings).toEqual([])
    expect(result.summary).toContain(`${dropCount} drops verified`)
    expect(result.marks).toHaveLength(dropCount)
    expect(result.marks.every((c) => c.includes('ok'))).toBe(true)
    expect(result.history.every((h) => h.bet === 25 && h.verified === true)).toBe(true)

    // Seeds mode, the page's default: the room's desync checks all agreed with the page's simulation.
    expect(result.delivery).toBe('seeds')
    expect(result.seeds.checks).toBeGreaterThan(0)
    expect(result.seeds.mismatches).toBe(0)

    // The same hashes reached another client, and are in the ledger.
    for (const v of mine) {
      const settled = await observer.take((m) => m.type === 'settled' && m.dropId === v.dropId)
      expect(settled.stateHash).toBe(v.localStateHash)
      expect(settled.bucket).toBe(v.localBucket)
      const audit = await server.audit(`/api/audit/drops/${v.dropId}`)
      expect(audit.matches).toBe(true)
      expect(audit.drop).toMatchObject({ playerId: result.playerId, status: 'settled', bucket: v.localBucket, ticks: v.localTicks, stateHash: v.localStateHash, bet: 25 })
    }
    await observer.close()

    // The balance shown is the ledger's.
    const me = await server.api('GET', '/api/me', { token: await sessionToken(page) })
    expect(me.body.balance).toBe(result.balance)
    // Summed in milli-credits: payouts carry up to three decimals.
    const paid = result.history.reduce((sum, h) => sum + Math.round(h.payout * 1000) - h.bet * 1000, 0)
    expect(Math.round(result.balance * 1000)).toBe(Math.round(startBalance * 1000) + paid)

    // The board is drawn: many colours on the canvas, pegs lit.
    const canvas = await canvasStats(page)
    expect(canvas.colors).toBeGreaterThan(100)
    expect(canvas.bright).toBeGreaterThan(500)
    const after = await screenshot(page, 'player', { fullPage: true })
    expect(after.distinctColors).toBeGreaterThan(50)
    expect(after.nonBackgroundShare).toBeGreaterThan(0.2)

    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('sets the client seed, rotates, and verifies a revealed drop in the browser', async () => {
    const page = await openPlayer()
    const token = await sessionToken(page)

    await page.fill('#client-seed', 'my lucky seed')
    await page.click('#client-seed-form button')
    await waitInPage(page, 'the client seed to be set', () => /my lucky seed/.test(document.querySelector('#message').textContent))
    expect((await server.api('GET', '/api/me', { token })).body.clientSeed).toBe('my lucky seed')

    const committed = await page.textContent('#seed-hash')
    await page.click('#drop')
    await page.click('#drop')
    await waitInPage(page, 'two verifications', () => window.__plinko.verifications.length >= 2)
    const { drops } = (await server.api('GET', '/api/drops', { token })).body
    expect(drops).toHaveLength(2)
    for (const drop of drops) expect(drop).toMatchObject({ clientSeed: 'my lucky seed', serverSeedHash: committed })
    expect(await page.textContent('#seed-nonce')).toBe('2')

    // Rotation reveals the seed behind the committed hash.
    await page.click('#rotate')
    const reveal = await waitInPage(page, 'the reveal', () => window.__plinko.lastReveal)
    expect(reveal.previousServerSeedHash).toBe(committed)
    expect(reveal.matchesCommitment).toBe(true)
    expect(await page.textContent('#revealed-check')).toContain('✓')
    expect(await page.textContent('#seed-hash')).not.toBe(committed)

    // Verify the older drop from its row: sha256 commitment, HMAC drop seed and the outcome, all in the page.
    await waitInPage(page, 'revealed drops in the history', () => window.__plinko.history.filter((h) => h.revealed).length === 2)
    const oldest = Math.min(...drops.map((d) => d.id))
    await page.click(`#history tr[data-drop-id="${oldest}"] button`)
    const [check] = await waitInPage(page, 'the fairness check', () => window.__plinko.fairnessChecks.length > 0 && window.__plinko.fairnessChecks)
    expect(check.dropId).toBe(oldest)
    expect(check.ok).toBe(true)
    expect(check.checks).toEqual({ commitment: true, dropSeed: true, bucket: true, ticks: true, stateHash: true })
    const stored = drops.find((d) => d.id === oldest)
    expect(check.dropSeed).toBe(stored.dropSeed)
    expect(await page.textContent('#verify-verdict')).toContain('verified in your browser')

    // Any seeds, typed in.
    await page.click('#fairness details summary')
    await page.fill('#seeds-server', reveal.previousServerSeed)
    await page.fill('#seeds-client', 'my lucky seed')
    await page.fill('#seeds-nonce', String(stored.nonce))
    await page.click('#seeds-form button')
    const typed = await waitInPage(page, 'the typed-in check', () => window.__plinko.fairnessChecks.length > 1 && window.__plinko.fairnessChecks[1])
    expect(typed).toMatchObject({ dropSeed: stored.dropSeed, bucket: stored.bucket, ticks: stored.ticks, stateHash: stored.stateHash, serverSeedHash: committed })

    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('warns loudly when the server\'s outcome is not what the engine computes', async () => {
    const page = await chromium.newPage()
    // A man in the middle alters the final state hash in `settled` messages.
    await tamperSettledStateHash(page)
    await page.goto(`${server.base}/`)
    await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
    await page.click('#drop')
    const [v] = await waitInPage(page, 'a verification', () => window.__plinko.verifications.length > 0 && window.__plinko.verifications)
    expect(v.verified).toBe(false)
    expect(v.localBucket).toBe(v.serverBucket)
    expect(v.localStateHash).not.toBe(v.serverStateHash)
    // The ledger has the hash the page computed.
    expect((await server.audit(`/api/audit/drops/${v.dropId}`)).drop.stateHash).toBe(v.localStateHash)
    expect(await page.isVisible('#alert')).toBe(true)
    expect(await page.textContent('#alert')).toContain(`Drop #${v.dropId} did NOT verify`)
    await waitInPage(page, 'the history mark', () => document.querySelector('#history .mark.bad') !== null)
    expect(await page.getAttribute(`#history tr[data-drop-id="${v.dropId}"]`, 'class')).toBe('bad')
    expect(await page.textContent('#verify-summary')).toContain('did NOT verify')
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('changes rooms and keeps verifying', async () => {
    const page = await openPlayer()
    await page.selectOption('#rows', '8')
    await page.selectOption('#risk', 'high')
    await waitInPage(page, 'room 8-high', () => window.__plinko.room === '8-high')
    await page.click('#drop')
    const [v] = await waitInPage(page, 'a verification', () => window.__plinko.verifications.length > 0 && window.__plinko.verifications)
    expect(v).toMatchObject({ room: '8-high', verified: true })
    // The choice is remembered.
    await page.reload()
    await waitInPage(page, 'the page to rejoin 8-high', () => window.__plinko?.room === '8-high')
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('works on a phone-sized touch screen', async () => {
    const page = await openPlayer({ viewport: { width: 390, height: 844 }, isMobile: true, hasTouch: true, deviceScaleFactor: 2 })
    const layout = await page.evaluate(() => ({
      scrollWidth: document.scrollingElement.scrollWidth,
      innerWidth: window.innerWidth,
      canvas: document.querySelector('#board').getBoundingClientRect().toJSON(),
      drop: document.querySelector('#drop').getBoundingClientRect().toJSON()
    }))
    expect(layout.scrollWidth).toBeLessThanOrEqual(layout.innerWidth)
    expect(layout.canvas.width).toBeGreaterThan(300)
    expect(layout.canvas.right).toBeLessThanOrEqual(layout.innerWidth)
    expect(layout.drop.height).toBeGreaterThanOrEqual(44)
    await page.tap('#drop')
    await waitInPage(page, 'a verification', () => window.__plinko.verifications.length > 0)
    expect((await page.evaluate(() => window.__plinko.verifications))[0].verified).toBe(true)
    const canvas = await canvasStats(page)
    expect(canvas.width).toBeGreaterThan(600) // device pixels: drawn at the screen's pixel ratio
    expect(canvas.colors).toBeGreaterThan(100)
    const shot = await screenshot(page, 'player-phone')
    expect(shot.distinctColors).toBeGreaterThan(50)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
