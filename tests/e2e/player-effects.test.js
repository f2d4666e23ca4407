/**
 * The player page's look and feel (issue #12), in Chromium against the real
 * server: peg glows, bucket pops, the floating payout of a win of 2× or
 * more and the celebration of one of 10× or more, all from the page's own
 * simulation of the drop (the test recomputes the same peg contacts in
 * Node); own balls told apart from others'; and the Web Audio sounds: none
 * before the first user gesture, ticks and a landing after it, muting
 * remembered across a reload. Outcomes are chosen ahead: the test reads the
 * player's active server seed from the in-process server and picks the
 * client seed (helpers/player-page.js).
 */
import { describe, it, expect } from 'vitest'
import { createBoard, simulateDrop, deriveDropSeed } from '../../engine/index.js'
import { pegContacts } from '../../client/peg-contacts.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer, screenshotBoth, expectNotBlank, activeServerSeed, clientSeedFor, setClientSeed, canvasStats } from './helpers/player-page.js'
import { GameClient } from '../server/helpers/game-client.js'

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

/** Waits until drop `dropId`'s result has been revealed on the page (landed on screen and settled). */
function revealed (page, count) {
  return waitInPage(page, `${count} revealed results`, (n) => window.__plinko.recent.length >= n, count)
}

describe('player page: effects and sound', () => {
  it('glows the pegs the simulation hit, pops the bucket, floats the payout of a 2×+ win and celebrates a 10×+ one', async () => {
    const page = await openPlayer(chromium, server)
    const playerId = await page.evaluate(() => window.__plinko.playerId)
    const { serverSeed, nextNonce } = await activeServerSeed(server, playerId)

    // A big win first (≥ 10×), on 16 rows, medium risk.
    const big = await clientSeedFor({ serverSeed, nonce: nextNonce, rows: 16, risk: 'medium', wanted: (m) => m >= 10 })
    await setClientSeed(page, big.clientSeed)
    await page.fill('#bet', '100')
    await page.click('#drop')
    await revealed(page, 1)
    const afterBig = await page.evaluate(() => ({ effects: window.__plinko.effects, history: window.__plinko.history, recent: window.__plinko.recent }))
    const bigDrop = afterBig.history[0]
    expect(bigDrop.multiplier).toBe(big.multiplier)
    expect(afterBig.recent[0]).toMatchObject({ dropId: bigDrop.dropId, multiplier: big.multiplier, bucket: big.bucket })
    // Every peg contact of the simulated path glowed (the same contacts, recomputed here from the same seed).
    const board = createBoard({ rows: 16, risk: 'medium' })
    const path = simulateDrop(board, await deriveDropSeed(serverSeed, big.clientSeed, nextNonce), { trajectory: true })
    const contacts = pegContacts(board, path.trajectory)
    expect(contacts.length).toBeGreaterThan(16)
    expect(afterBig.effects.pegGlows).toBeLessThanOrEqual(contacts.length)
    expect(afterBig.effects.pegGlows).toBeGreaterThanOrEqual(Math.floor(contacts.length * 0.9))
    expect(afterBig.effects.bucketPops).toBe(1)
    expect(afterBig.effects.bursts).toBe(1)
    expect(afterBig.effects.floaterTexts).toEqual([`+${bigDrop.payout.toLocaleString('en-US')}`])
    const celebrating = await screenshotBoth(page, 'player-big-win')
    expectNotBlank(expect, celebrating)

    // A small win (2× to 10×): the payout floats, no celebration. Then a loss: neither.
    const medium = await clientSeedFor({ serverSeed, nonce: nextNonce + 1, rows: 16, risk: 'medium', wanted: (m) => m >= 2 && m < 10 })
    await setClientSeed(page, medium.clientSeed)
    await page.click('#drop')
    await revealed(page, 2)
    const loss = await clientSeedFor({ serverSeed, nonce: nextNonce + 2, rows: 16, risk: 'medium', wanted: (m) => m < 1 })
    await setClientSeed(page, loss.clientSeed)
    await page.click('#drop')
    await revealed(page, 3)
    const after = await page.evaluate(() => ({ effects: window.__plinko.effects, history: window.__plinko.history, verifications: window.__plinko.verifications }))
    expect(after.history.map((h) => h.multiplier)).toEqual([loss.multiplier, medium.multiplier, big.multiplier])
    expect(after.effects.bucketPops).toBe(3)
    expect(after.effects.bursts).toBe(1)
    expect(after.effects.floaterTexts).toEqual([`+${bigDrop.payout.toLocaleString('en-US')}`, `+${after.history[1].payout.toLocaleString('en-US')}`])
    expect(after.verifications.every((v) => v.verified)).toBe(true)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  // In a worker on an OffscreenCanvas (Chromium's path), and on the main thread (browsers without it: ?board=main), by the same drawing code.
  for (const where of ['worker', 'main']) {
    it(`draws own balls apart from the others', with trails (the board drawn in ${where === 'worker' ? 'a worker' : 'the main thread'})`, async () => {
      const page = await openPlayer(chromium, server, { path: where === 'worker' ? '/' : '/?board=main' })
      expect(await page.evaluate(() => window.__plinko.boardDrawnIn)).toBe(where)
      const other = (await server.api('POST', '/api/session')).body
      const client = await GameClient.connect(server.wsUrl(other.token))
      client.send({ type: 'join', room: '16-medium' })
      await client.take('joined')
      client.send({ type: 'drop', bet: 5 })
      await page.click('#drop')
      const frame = await waitInPage(page, 'own and another player\'s ball in one frame', () => {
        const f = window.__plinko.lastFrame
        return f.mine >= 1 && f.balls - f.mine >= 1 && f
      })
      expect(frame.unknown).toBe(0)
      // Own balls are warm (pink halo), the others' cool: both colours are on the canvas at once.
      // Read where the board is drawn (the worker's OffscreenCanvas, or the page's canvas).
      const colours = await page.evaluate(async () => {
        const { data } = await window.__plinko.boardPixels()
        let warm = 0; let cool = 0
        for (let i = 0; i < data.length; i += 4) {
          const [r, g, b] = [data[i], data[i + 1], data[i + 2]]
          if (r > 200 && g < 140 && b > 100 && b < 190) warm++
          if (b > 150 && r < 150 && g > 110 && g < 170) cool++
        }
        return { warm, cool }
      })
      expect(colours.warm).toBeGreaterThan(5)
      expect(colours.cool).toBeGreaterThan(5)
      await client.take('settled', 60_000)
      await client.close()
      expect((await canvasStats(page)).colors).toBeGreaterThan(100)
      expect(page.problems).toEqual([])
      await page.context().close()
    })
  }

  it('plays no sound before the first gesture; ticks and a landing after it; mute is remembered', async () => {
    const page = await openPlayer(chromium, server)
    // A drop with no gesture yet (from script): silence, and no audio context at all.
    await page.evaluate(() => window.__plinko.drop())
    await revealed(page, 1)
    expect(await page.evaluate(() => window.__plinko.sound)).toMatchObject({ unlocked: false, state: null, ticks: 0, landings: 0, muted: false })

    // The first click unlocks audio; Space drops; its pegs tick and its landing sounds.
    await page.locator('body').click({ position: { x: 5, y: 300 } })
    await waitInPage(page, 'the audio context to run', () => window.__plinko.sound.state === 'running')
    await page.keyboard.press('Space')
    await revealed(page, 2)
    const heard = await page.evaluate(() => window.__plinko.sound)
    expect(heard.unlocked).toBe(true)
    expect(heard.ticks).toBeGreaterThan(10)
    expect(heard.landings).toBe(1)

    // Muted (button): nothing more plays, and the choice survives a reload.
    await page.click('#mute')
    expect(await page.getAttribute('#mute', 'aria-pressed')).toBe('true')
    expect(await page.evaluate(() => localStorage.getItem('plinko.muted'))).toBe('1')
    // Space on the focused mute button is the button's: drop with nothing focused.
    await page.locator('body').click({ position: { x: 5, y: 300 } })
    await page.keyboard.press('Space')
    await revealed(page, 3)
    expect(await page.evaluate(() => window.__plinko.sound)).toMatchObject({ muted: true, ticks: heard.ticks, landings: 1 })
    await page.reload()
    await waitInPage(page, 'the page to join again', () => window.__plinko?.ready === true)
    expect(await page.evaluate(() => window.__plinko.sound.muted)).toBe(true)
    expect(await page.getAttribute('#mute', 'aria-pressed')).toBe('true')
    // M unmutes.
    await page.locator('body').click({ position: { x: 5, y: 300 } })
    await page.keyboard.press('KeyM')
    expect(await page.evaluate(() => ({ muted: window.__plinko.sound.muted, stored: localStorage.getItem('plinko.muted') }))).toEqual({ muted: false, stored: '0' })
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
