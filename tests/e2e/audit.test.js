/**
 * The operator page (/audit) in real Chromium (issue #4): sign in with the
 * operator token, look up stored drops by id and by seeds, see the stored
 * record next to the server's and the browser's re-simulations and that
 * they match, replay the drop on the canvas (play, step, scrub), list a
 * player's drops and chart a room's measured RTP against the calibrated one.
 */
import { describe, it, expect } from 'vitest'
import { writeFileSync, mkdirSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { OPERATOR_TOKEN } from './helpers/arena-server.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium, playerWithSettledDrops } from './helpers/testbed.js'
import { imageStats } from './helpers/png.js'

const ROOM = '12-high'
const DROPS = 6

let server
let chromium
let player
let drops

serverAndChromium({ tickRate: 180 }, async (started) => {
  ({ server, chromium } = started)
  // A player drops a few balls over the protocol and waits for them to settle.
  ;({ player, drops } = await playerWithSettledDrops(server, { room: ROOM, drops: DROPS, bet: 100 }))
})

async function openAudit () {
  const page = await chromium.newPage({ viewport: { width: 1280, height: 1000 } })
  await page.goto(`${server.base}/audit`)
  await waitInPage(page, 'the audit page', () => window.__audit !== undefined)
  return page
}

describe('operator page in Chromium', () => {
  it('asks for the operator token and keeps it for the tab only', async () => {
    const page = await openAudit()
    expect(await page.evaluate(() => window.__audit.signedIn)).toBe(false)
    await page.fill('#token', 'not-the-operator-token')
    await page.click('#sign-in')
    await waitInPage(page, 'the refusal', () => /not the operator token/.test(document.querySelector('#login-message').textContent))
    expect(await page.evaluate(() => window.__audit.signedIn)).toBe(false)

    await page.fill('#token', OPERATOR_TOKEN)
    await page.click('#sign-in')
    await waitInPage(page, 'sign-in', () => window.__audit.signedIn)
    expect(await page.evaluate(() => sessionStorage.getItem('plinko.operatorToken'))).toBe(OPERATOR_TOKEN)
    expect(await page.evaluate(() => localStorage.length)).toBe(0)
    await page.reload()
    await waitInPage(page, 'sign-in from sessionStorage', () => window.__audit?.signedIn)
    // The refused attempt is a message only (the token check answers 200): nothing in the console.
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('looks up a stored drop, shows it matches, and replays it', async () => {
    const page = await openAudit()
    await page.evaluate((token) => sessionStorage.setItem('plinko.operatorToken', token), OPERATOR_TOKEN)
    await page.reload()
    await waitInPage(page, 'sign-in', () => window.__audit?.signedIn)

    const drop = drops[drops.length - 1]
    await page.fill('#drop-id', String(drop.id))
    await page.click('#id-form button')
    const [lookup] = await waitInPage(page, 'the look-up', () => window.__audit.lookups.length > 0 && window.__audit.lookups)
    expect(lookup).toMatchObject({ dropId: drop.id, matches: true, serverMatches: true, browserMatches: true, settled: true })
    const fields = Object.fromEntries(lookup.rows.map((r) => [r.field, r]))
    expect(fields.stateHash).toMatchObject({ stored: drop.stateHash, server: drop.stateHash, browser: drop.stateHash, agree: true })
    expect(fields.ticks).toMatchObject({ stored: drop.ticks, browser: drop.ticks, agree: true })
    expect(fields.bucket).toMatchObject({ stored: drop.bucket, browser: drop.bucket, agree: true })
    expect(await page.getAttribute('#match-banner', 'data-matches')).toBe('true')
    expect(await page.textContent('#match-banner')).toContain('MATCH')

    // Replay: loaded at tick 0 of the drop's own ticks; play at 4× to the landing.
    let replay = await page.evaluate(() => window.__audit.replay)
    expect(replay).toMatchObject({ tick: 0, ticks: drop.ticks, playing: false, bucket: drop.bucket })
    await page.selectOption('#speed', '4')
    await page.click('#play')
    await waitInPage(page, 'the replay to play', () => window.__audit.replay.tick > 0)
    const midway = await page.screenshot()
    await waitInPage(page, 'the replay to land', () => !window.__audit.replay.playing && window.__audit.replay.tick === window.__audit.replay.ticks)
    expect(await page.textContent('#tick-readout')).toContain(`bucket ${drop.bucket}`)
    await page.click('#step-back')
    await page.click('#step-back')
    replay = await page.evaluate(() => window.__audit.replay)
    expect(replay.tick).toBe(drop.ticks - 2)
    await page.click('#step-forward')
    expect((await page.evaluate(() => window.__audit.replay)).tick).toBe(drop.ticks - 1)
    await page.evaluate(() => {
      const scrub = document.querySelector('#scrub')
      scrub.value = '40'
      scrub.dispatchEvent(new Event('input'))
    })
    expect((await page.evaluate(() => window.__audit.replay)).tick).toBe(40)

    const canvas = await page.evaluate(() => {
      const c = document.querySelector('#replay-canvas')
      const { data } = c.getContext('2d').getImageData(0, 0, c.width, c.height)
      const colors = new Set()
      for (let i = 0; i < data.length; i += 4) colors.add((data[i] << 16) | (data[i + 1] << 8) | data[i + 2])
      return colors.size
    })
    expect(canvas).toBeGreaterThan(100)
    expect(imageStats(midway).distinctColors).toBeGreaterThan(50)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('looks up a drop by its revealed seeds, lists a player\'s drops and charts a room\'s RTP', async () => {
    const rotated = (await server.api('POST', '/api/seeds/rotate', { token: player.token })).body
    const page = await openAudit()
    await page.fill('#token', OPERATOR_TOKEN)
    await page.click('#sign-in')
    await waitInPage(page, 'sign-in', () => window.__audit.signedIn)

    // By seeds: the server seed revealed by the rotation, the client seed and a nonce.
    const drop = drops.find((d) => d.nonce === 2)
    await page.click('#seeds-details summary')
    await page.fill('#seed-server', rotated.previousServerSeed)
    await page.fill('#seed-client', drop.clientSeed)
    await page.fill('#seed-nonce', '2')
    await page.selectOption('#seed-rows', '12')
    await page.selectOption('#seed-risk', 'high')
    await page.click('#seeds-form button')
    const bySeeds = await waitInPage(page, 'the seed look-up', () => window.__audit.lookups.length > 0 && window.__audit.lookups[0])
    expect(bySeeds).toMatchObject({ dropId: drop.id, matches: true, browserMatches: true })
    const fields = Object.fromEntries(bySeeds.rows.map((r) => [r.field, r]))
    expect(fields.serverSeedHash).toMatchObject({ stored: drop.serverSeedHash, browser: drop.serverSeedHash, agree: true })
    expect(fields.dropSeed).toMatchObject({ stored: drop.dropSeed, browser: drop.dropSeed, agree: true })
    expect(await page.evaluate(() => window.__audit.replay.ticks)).toBe(drop.ticks)

    // The player's drops; a click looks one up.
    await page.fill('#player-id', player.playerId)
    await page.click('#player-form button')
    await waitInPage(page, 'the player\'s drops', (n) => document.querySelectorAll('#player-drops tr[data-drop-id]').length === n, DROPS)
    await page.click(`#player-drops tr[data-drop-id="${drops[0].id}"]`)
    await waitInPage(page, 'the second look-up', () => window.__audit.lookups.length > 1)
    expect(await page.evaluate(() => window.__audit.lookups[1])).toMatchObject({ dropId: drops[0].id, matches: true })

    // Room statistics with the two charts.
    await page.selectOption('#stats-rows', '12')
    await page.selectOption('#stats-risk', 'high')
    await page.click('#stats-form button')
    const stats = await waitInPage(page, 'the room statistics', (room) => window.__audit.stats?.room === room && window.__audit.stats, ROOM)
    expect(stats).toMatchObject({ room: ROOM, settled: DROPS, totalBet: DROPS * 100 })
    expect(stats.bucketCounts.reduce((a, b) => a + b, 0)).toBe(DROPS)
    const charts = await page.evaluate(() => [...document.querySelectorAll('#stats svg.chart')].map((svg) => ({
      bars: svg.querySelectorAll('rect').length,
      lines: svg.querySelectorAll('line, polyline').length,
      label: svg.getAttribute('aria-label')
    })))
    expect(charts).toHaveLength(2)
    expect(charts[0].bars).toBe(13)
    expect(charts[1].label).toContain('RTP')
    expect(await page.textContent('#stats')).toContain('calibrated 99.')

    mkdirSync(join(tmpdir(), 'plinko-e2e-screenshots'), { recursive: true })
    const file = join(tmpdir(), 'plinko-e2e-screenshots', 'audit.png')
    const png = await page.screenshot({ fullPage: true })
    writeFileSync(file, png)
    console.info(`[e2e] screenshot ${file}`)
    const shot = imageStats(png)
    expect(shot.distinctColors).toBeGreaterThan(50)
    expect(shot.nonBackgroundShare).toBeGreaterThan(0.2)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
