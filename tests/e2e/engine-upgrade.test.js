/**
 * Drops a 1.0.0 server recorded, verified in the browser after the upgrade
 * (issue #11): the server opens the ledger a real 1.0.0 server left behind
 * (tests/fixtures/ledger-1.0.0) and decides new drops under the newest
 * engine. The player page re-simulates its history under each drop's own
 * version and marks every one verified; its fairness panel verifies a
 * revealed 1.0.0 drop; the operator page replays a 1.0.0 drop with the
 * stored record, the server's and the browser's re-simulation agreeing.
 */
import { describe, it, expect } from 'vitest'
import { ENGINE_VERSION } from '../../engine/index.js'
import { OPERATOR_TOKEN } from './helpers/arena-server.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { ledgerFixture, fixtureDrops } from '../helpers/ledger-fixture.js'

const fixture = ledgerFixture('1.0.0')
const recorded = fixtureDrops(fixture)
const a = fixture.players.a

let server
let chromium
serverAndChromium({ tickRate: 180, ledger: fixture.sqliteFile }, (started) => ({ server, chromium } = started))

describe('a 1.0.0 ledger after the upgrade, in Chromium', () => {
  it('the player page verifies every 1.0.0 drop of its history under 1.0.0', async () => {
    const page = await chromium.newPage({ viewport: { width: 1280, height: 900 } })
    // The recorded player's session is in place before any page script runs:
    // set after a first load, the page's own new session could overwrite it.
    await page.addInitScript(({ token, playerId }) => localStorage.setItem('plinko.session', JSON.stringify({ token, playerId })), a)
    await page.goto(`${server.base}/`)
    await waitInPage(page, 'the page to join its room', () => window.__plinko?.ready === true)
    expect(await page.evaluate(() => window.__plinko.playerId)).toBe(a.playerId)
    const own = recorded.filter((d) => d.player_id === a.playerId)
    const verifications = await waitInPage(page, 'the history to be verified', (count) => window.__plinko.verifications.length >= count && window.__plinko.verifications, own.length)
    expect(verifications).toHaveLength(own.length)
    for (const v of verifications) {
      expect(v, `drop ${v.dropId}`).toMatchObject({ verified: true, source: 'ledger' })
      const row = own.find((d) => d.id === v.dropId)
      expect(v.localStateHash).toBe(row.state_hash ?? v.serverStateHash) // the in-flight ones settled at start-up, under 1.0.0
    }
    expect(await page.evaluate(() => window.__plinko.warnings)).toEqual([])

    // The fairness panel: a revealed 1.0.0 drop, verified in the browser.
    const revealed = own.find((d) => d.server_seed_hash === a.revealedServerSeedHash)
    await page.fill('#verify-id', String(revealed.id))
    await page.click('#verify-form button')
    const [check] = await waitInPage(page, 'the verification', () => window.__plinko.fairnessChecks.length > 0 && window.__plinko.fairnessChecks)
    expect(check).toMatchObject({ dropId: revealed.id, engineVersion: '1.0.0', ok: true, bucket: revealed.bucket, stateHash: revealed.state_hash })
    expect(await page.textContent('#verify-verdict')).toContain('verified in your browser')

    // A new drop now is decided under the newest version, and verified under it.
    await page.evaluate(() => window.__plinko.drop())
    const fresh = await waitInPage(page, 'the new drop to settle', (count) => window.__plinko.verifications.length > count && window.__plinko.verifications.at(-1), own.length)
    expect(fresh.verified).toBe(true)
    const record = (await server.api('GET', `/api/drops/${fresh.dropId}`, { token: a.token })).body
    expect(record.engineVersion).toBe(ENGINE_VERSION)
    expect(page.problems).toEqual([])
    await page.context().close()
  })

  it('the operator page replays a 1.0.0 drop under 1.0.0, by id and by seeds', async () => {
    const page = await chromium.newPage({ viewport: { width: 1280, height: 1000 } })
    await page.goto(`${server.base}/audit`)
    await page.evaluate((token) => sessionStorage.setItem('plinko.operatorToken', token), OPERATOR_TOKEN)
    await page.reload()
    await waitInPage(page, 'sign-in', () => window.__audit?.signedIn)
    const drop = recorded.find((d) => d.server_seed_hash === a.revealedServerSeedHash && d.room === '16-high')
    await page.fill('#drop-id', String(drop.id))
    await page.click('#id-form button')
    const [byId] = await waitInPage(page, 'the look-up', () => window.__audit.lookups.length > 0 && window.__audit.lookups)
    expect(byId).toMatchObject({ dropId: drop.id, matches: true, serverMatches: true, browserMatches: true })
    const fields = Object.fromEntries(byId.rows.map((r) => [r.field, r]))
    expect(fields.engineVersion).toMatchObject({ stored: '1.0.0', server: '1.0.0', browser: '1.0.0', agree: true })
    expect(fields.stateHash).toMatchObject({ stored: drop.state_hash, browser: drop.state_hash, agree: true })
    expect(await page.evaluate(() => window.__audit.replay.ticks)).toBe(drop.ticks)

    await page.click('#seeds-details summary')
    await page.fill('#seed-server', a.revealedServerSeed)
    await page.fill('#seed-client', drop.client_seed)
    await page.fill('#seed-nonce', String(drop.nonce))
    await page.selectOption('#seed-rows', String(drop.rows))
    await page.selectOption('#seed-risk', drop.risk)
    await page.selectOption('#seed-engine', '1.0.0')
    await page.click('#seeds-form button')
    const bySeeds = await waitInPage(page, 'the seeds look-up', () => window.__audit.lookups.length > 1 && window.__audit.lookups[1])
    expect(bySeeds).toMatchObject({ dropId: drop.id, matches: true })
    expect(bySeeds.recorded).toEqual([{ id: drop.id, matches: true }])
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
