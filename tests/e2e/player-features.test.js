/**
 * The features players expect (issue #12), in Chromium against the real
 * server: the recent-results strip, the room's live feed with its player
 * count and big wins, the session stats, the hotkeys (and their hints gone
 * on touch screens), auto-bet (stop on profit and on loss, bet changes on
 * wins and losses, stopping on a lost connection and resuming), ½ / 2×
 * clamped to the balance, board changes refused while own balls fall, and
 * game recall (any past drop replayed from its seed with its fairness data).
 */
import { describe, it, expect } from 'vitest'
import { createBoard } from '../../engine/index.js'
import { toCredits, toMilli } from '../../protocol/payout.js'
import { bucketColors } from '../../client/board-renderer.js'
import { BIG_WIN } from '../../client/live-feed.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, screenshotBoth, expectNotBlank, activeServerSeed, clientSeedFor, setClientSeed, canvasStats, PHONE } from './helpers/player-page.js'
import { GameClient } from '../server/helpers/game-client.js'

let server
let chromium
// Three times real time: outcomes are the same, the page measures the rate.
serverAndChromium({ tickRate: 180 }, (started) => ({ server, chromium } = started))

const allSettled = (page, count) => waitInPage(page, `${count} settled drops`, (n) => window.__plinko.history.length >= n && window.__plinko.history.every((h) => h.payout !== null) && window.__plinko.pendingVerifications === 0, count, 120_000)

describe('player page features', () => {
  it('shows the recent results, the room feed with players and big wins, and the session stats', async () => {
    const page = await openPlayer(chromium, server)
    // Another player in the room, whose next drop is a big win.
    const other = (await server.api('POST', '/api/session')).body
    const { serverSeed } = await activeServerSeed(server, other.playerId)
    const big = await clientSeedFor({ serverSeed, nonce: 0, rows: 16, risk: 'medium', wanted: (m) => m >= 10 })
    const client = await GameClient.connect(server.wsUrl(other.token))
    client.send({ type: 'join', room: '16-medium' })
    await client.take('joined')
    await waitInPage(page, 'two players in the room', () => window.__plinko.players === 2, undefined, 30_000)
    expect(await page.textContent('#room-players')).toBe('2 players')

    client.send({ type: 'drop', bet: 50, clientSeed: big.clientSeed })
    await page.fill('#bet', '20')
    await page.locator('body').click({ position: { x: 5, y: 300 } })
    for (let i = 0; i < 3; i++) await page.keyboard.press('Space')
    await allSettled(page, 3)
    await waitInPage(page, 'three results and four feed rows', () => window.__plinko.recent.length === 3 && window.__plinko.feed.length === 4)
    const seen = await page.evaluate(() => ({ recent: window.__plinko.recent, feed: window.__plinko.feed, history: window.__plinko.history, session: window.__plinko.session, chips: [...document.querySelectorAll('#recent li')].map((li) => ({ text: li.textContent, background: li.style.background })) }))

    // The strip: own results, newest first, coloured like their buckets.
    const colors = bucketColors(createBoard({ rows: 16, risk: 'medium' }).multipliers)
    expect(seen.recent.map((r) => r.dropId).sort()).toEqual(seen.history.map((h) => h.dropId).sort())
    for (const r of seen.recent) {
      expect(r.color).toBe(colors[r.bucket])
      expect(r.multiplier).toBe(seen.history.find((h) => h.dropId === r.dropId).multiplier)
    }
    expect(seen.chips).toHaveLength(3)
    expect(seen.chips.every((c) => c.background.startsWith('rgb'))).toBe(true)

    // The feed: every drop of the room with who, bet, multiplier and payout; the other's big win highlighted.
    const theirs = seen.feed.find((f) => !f.mine)
    expect(theirs).toMatchObject({ player: other.playerId, bet: 50, multiplier: big.multiplier, big: true })
    expect(seen.feed.filter((f) => f.mine)).toHaveLength(3)
    for (const f of seen.feed.filter((f) => f.mine)) {
      const own = seen.history.find((h) => h.dropId === f.dropId)
      expect(f).toMatchObject({ bet: 20, multiplier: own.multiplier, payout: own.payout, player: await page.evaluate(() => window.__plinko.playerId) })
    }
    // Big wins (≥ BIG_WIN×) are highlighted, whoever made them: the other's, and any of the page's own three that happened to be one.
    for (const f of seen.feed) expect(f.big).toBe(f.multiplier >= BIG_WIN)
    expect(await page.locator('#feed tr.big').count()).toBe(seen.feed.filter((f) => f.multiplier >= BIG_WIN).length)

    // The session: wagered, profit, drops and the chart's points.
    const profit = toCredits(seen.history.reduce((sum, h) => sum + toMilli(h.payout) - toMilli(h.bet), 0))
    expect(seen.session).toMatchObject({ wagered: 60, profit, drops: 3, points: 4 })
    expect(await page.textContent('#stat-wagered')).toBe('60')
    expect(await page.textContent('#stat-drops')).toBe('3')
    expect(await page.getAttribute('#profit-chart', 'data-points')).toBe('4')
    await client.close()
    expectNotBlank(expect, await screenshotBoth(page, 'player-feed'))
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('has hotkeys (Space, S, D, A) that leave typing alone, ½ / 2× clamped to the balance; no hints on touch screens', async () => {
    const page = await openPlayer(chromium, server)
    await page.fill('#bet', '10')
    await page.locator('body').click({ position: { x: 5, y: 300 } })
    await page.keyboard.press('Space')
    await waitInPage(page, 'a drop from Space', () => window.__plinko.history.length === 1)
    await page.keyboard.press('KeyS')
    expect(await page.inputValue('#bet')).toBe('5')
    await page.keyboard.press('KeyD')
    await page.keyboard.press('KeyD')
    expect(await page.inputValue('#bet')).toBe('20')

    // Typing in a text field is typing.
    await page.focus('#client-seed')
    await page.keyboard.type(' sad ')
    expect(await page.inputValue('#bet')).toBe('20')
    expect(await page.inputValue('#client-seed')).toContain(' sad ')
    expect(await page.evaluate(() => window.__plinko.history.length)).toBe(1)

    // 2× never goes past the balance.
    await allSettled(page, 1)
    const balance = await page.evaluate(() => window.__plinko.balance)
    await page.fill('#bet', String(Math.floor(balance * 0.75)))
    await page.click('[data-bet="double"]')
    expect(Number(await page.inputValue('#bet'))).toBe(Math.floor(balance))
    await page.click('[data-bet="half"]')
    expect(Number(await page.inputValue('#bet'))).toBe(Math.floor(Math.floor(balance) / 2))

    // A starts and stops the auto-bet.
    await page.fill('#bet', '1')
    await page.fill('#auto-count', '100')
    await page.locator('body').click({ position: { x: 5, y: 300 } })
    await page.keyboard.press('KeyA')
    await waitInPage(page, 'the auto-bet to run', () => window.__plinko.auto?.running && window.__plinko.auto.sent >= 2)
    await page.keyboard.press('KeyA')
    const stopped = await waitInPage(page, 'the auto-bet to stop', () => window.__plinko.auto.running === false && window.__plinko.auto)
    expect(stopped.stopReason).toBe('stopped')
    expect(stopped.sent).toBeLessThan(100)
    expect(await page.isVisible('#key-hints')).toBe(true)
    expect(page.problems).toEqual([])
    await page.context().close()

    const phone = await openPlayer(chromium, server, { viewport: PHONE, isMobile: true, hasTouch: true, deviceScaleFactor: 2 })
    expect(await phone.evaluate(() => [...document.querySelectorAll('.key-hint')].every((k) => getComputedStyle(k).display === 'none'))).toBe(true)
    expect(await phone.isVisible('#key-hints')).toBe(false)
    expect(phone.problems).toEqual([])
    await phone.context().close()
  })

  it('auto-bets with stop on loss and a bet raised after each loss; and stops on profit', async () => {
    const page = await openPlayer(chromium, server)
    const playerId = await page.evaluate(() => window.__plinko.playerId)
    const { serverSeed, nextNonce } = await activeServerSeed(server, playerId)
    // Stop on loss: 200 at a bet of 10 doubled after each loss, reset after a win.
    await page.fill('#bet', '10')
    await page.fill('#auto-count', '40')
    await page.click('#auto-options summary')
    await page.fill('#auto-stop-loss', '200')
    await page.selectOption('#auto-on-loss', 'increase')
    await page.fill('#auto-loss-percent', '100')
    await page.click('#auto')
    const lossRun = await waitInPage(page, 'the stop on loss (or the end)', () => window.__plinko.auto && !window.__plinko.auto.running && window.__plinko.auto)
    await allSettled(page, lossRun.sent)
    const run = await page.evaluate(() => window.__plinko.auto)
    // Every settled result set the next bet by the rules.
    let bet = 10
    for (const entry of run.log) {
      expect(entry.betBefore).toBe(bet)
      bet = entry.win ? 10 : Math.round(bet * 2)
      expect(entry.betAfter).toBe(bet)
    }
    // Only results that came while the run was still sending can stop it (balls still falling after it stopped settle, and stop nothing).
    if (run.stopReason === 'loss') {
      const stopAt = run.log.findIndex((e) => e.whileRunning && -e.profit >= 200)
      expect(stopAt).toBeGreaterThanOrEqual(0)
      expect(run.log.slice(stopAt + 1).some((e) => e.whileRunning)).toBe(false)
      expect(await page.textContent('#auto-status')).toContain('stop on loss')
    } else {
      expect(run.stopReason).toBe('done')
      expect(run.sent).toBe(40)
      expect(run.log.filter((e) => e.whileRunning).every((e) => -e.profit < 200)).toBe(true)
    }
    // The bets the server took are those the rules gave (the first is the base bet; later ones follow results).
    const bets = (await page.evaluate(() => window.__plinko.history)).map((h) => h.bet)
    expect(bets).toContain(10)
    expect(new Set(bets).size).toBeGreaterThan(1)

    // Stop on profit: the next drop is a 10×+ win.
    const { nextNonce: nonce } = await activeServerSeed(server, playerId)
    expect(nonce).toBe(nextNonce + run.sent)
    const big = await clientSeedFor({ serverSeed, nonce, rows: 16, risk: 'medium', wanted: (m) => m >= 10 })
    await setClientSeed(page, big.clientSeed)
    await page.fill('#bet', '100')
    await page.fill('#auto-stop-loss', '')
    await page.fill('#auto-stop-profit', '300')
    await page.selectOption('#auto-on-loss', 'reset')
    await page.fill('#auto-count', '200')
    await page.click('#auto')
    const profitRun = await waitInPage(page, 'the stop on profit', () => window.__plinko.auto && !window.__plinko.auto.running && window.__plinko.auto)
    expect(profitRun.stopReason).toBe('profit')
    expect(profitRun.profit).toBeGreaterThanOrEqual(300)
    expect(profitRun.sent).toBeLessThan(200)
    expect(await page.textContent('#auto-status')).toContain('stop on profit')
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('stops the auto-bet with a message when the connection drops, and resumes it', async () => {
    const page = await openPlayer(chromium, server)
    await page.fill('#bet', '1')
    await page.fill('#auto-count', '12')
    await page.click('#auto')
    await waitInPage(page, 'a few auto drops', () => window.__plinko.auto?.sent >= 3)
    const connects = await page.evaluate(() => window.__plinko.connects)
    await page.evaluate(() => window.__plinko.dropConnection())
    const stopped = await waitInPage(page, 'the auto-bet to stop', () => window.__plinko.auto.running === false && window.__plinko.auto)
    expect(stopped.stopReason).toBe('disconnected')
    expect(await page.textContent('#auto-status')).toContain('connection was lost')
    expect(await page.isVisible('#auto-resume')).toBe(true)
    // Back in the room: resume with the bets that were left.
    await waitInPage(page, 'the page to rejoin', (n) => window.__plinko.connects > n && window.__plinko.ready, connects)
    await waitInPage(page, 'the resume button', () => !document.querySelector('#auto-resume').disabled)
    expect(await page.textContent('#auto-resume')).toContain(`${12 - stopped.sent} left`)
    await page.click('#auto-resume')
    const done = await waitInPage(page, 'the resumed run to finish', () => window.__plinko.auto.stopReason === 'done' && window.__plinko.auto)
    expect(done.sent).toBe(12)
    await allSettled(page, 12)
    const verifications = await page.evaluate(() => window.__plinko.verifications)
    expect(verifications.filter((v) => v.mine)).toHaveLength(12)
    expect(verifications.every((v) => v.verified)).toBe(true)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('refuses a board change while own balls fall, with a message, and allows it once they landed', async () => {
    const page = await openPlayer(chromium, server)
    await page.click('#drop')
    await page.click('#drop')
    await waitInPage(page, 'own balls in flight', () => window.__plinko.ownInFlight === 2)
    // Drawn once the playout buffer reaches their start tick (≥ 100 ms after `dropped`).
    await waitInPage(page, 'both own balls drawn', () => window.__plinko.lastFrame?.mine === 2)
    await page.selectOption('#rows', '8')
    expect(await page.evaluate(() => window.__plinko.room)).toBe('16-medium')
    expect(await page.inputValue('#rows')).toBe('16')
    expect(await page.textContent('#message')).toContain('Wait for your 2 balls in flight to land')
    // The balls are still drawn after the refusal.
    await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))))
    expect(await page.evaluate(() => window.__plinko.lastFrame.mine)).toBe(2)
    await waitInPage(page, 'the balls to land', () => window.__plinko.ownInFlight === 0)
    await page.selectOption('#rows', '8')
    await waitInPage(page, 'room 8-medium', () => window.__plinko.room === '8-medium')
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('recalls any past drop: replayed on the canvas from its seed, with its fairness data', async () => {
    const page = await openPlayer(chromium, server)
    await page.fill('#bet', '3')
    await page.fill('#auto-count', '10')
    await page.click('#auto')
    await allSettled(page, 10)
    // The last ten games are all recallable from the history.
    expect(await page.locator('#history .recall-button').count()).toBe(10)
    const token = await page.evaluate(() => JSON.parse(localStorage.getItem('plinko.session')).token)
    const { drops } = (await server.api('GET', '/api/drops', { token })).body
    const oldest = drops[drops.length - 1]
    await page.click(`#history tr[data-drop-id="${oldest.id}"] .recall-button`)
    const replay = await waitInPage(page, 'the replay to reach the landing', () => window.__plinko.recall?.open && !window.__plinko.recall.playing && window.__plinko.recall.tick === window.__plinko.recall.ticks && window.__plinko.recall)
    expect(replay).toMatchObject({ dropId: oldest.id, bucket: oldest.bucket, ticks: oldest.ticks, stateHash: oldest.stateHash, matches: true, chain: null })
    expect(replay.frames).toBeGreaterThan(10)
    expect(await page.textContent('#recall-verdict')).toContain('Replayed from its drop seed')
    expect(await page.textContent('#recall-data')).toContain(oldest.dropSeed)
    expect(await page.textContent('#recall-data')).toContain(oldest.serverSeedHash)
    expect(await page.textContent('#recall-server-seed')).toContain('secret')
    expect((await canvasStats(page, '#recall-board')).colors).toBeGreaterThan(100)
    // Step back one tick.
    await page.click('#recall-back')
    expect(await page.evaluate(() => window.__plinko.recall.tick)).toBe(oldest.ticks - 1)
    expectNotBlank(expect, await screenshotBoth(page, 'player-recall'))
    await page.click('#recall-close')
    expect(await page.evaluate(() => window.__plinko.recall.open)).toBe(false)

    // Once the seed is revealed, the recall checks the whole chain.
    await page.click('#rotate')
    await waitInPage(page, 'the reveal', () => window.__plinko.lastReveal)
    await page.click(`#history tr[data-drop-id="${oldest.id}"] .recall-button`)
    const full = await waitInPage(page, 'the verified recall', () => window.__plinko.recall?.open && window.__plinko.recall.chain !== null && window.__plinko.recall)
    expect(full).toMatchObject({ dropId: oldest.id, matches: true, chain: true })
    expect(await page.textContent('#recall-server-seed')).toMatch(/^[0-9a-f]{64}$/)
    expect(await page.textContent('#recall-verdict')).toContain('verified')
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
