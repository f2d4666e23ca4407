/**
 * Issue #24, item 18, in Chromium against the real server: the operator
 * page signs in through POST /api/audit/token-check (a 200 whatever the
 * token), so a wrong token, and an address blocked for too many of them,
 * are messages on the page with not one line in the console (Chromium logs
 * every 4xx or 5xx a page's request gets: the 403 of the old sign-in did).
 * The check counts wrong tokens all the same: past AUTH_FAILURE_LIMIT the
 * audit routes answer this address 429.
 */
import { describe, it, expect } from 'vitest'
import { OPERATOR_TOKEN } from './helpers/arena-server.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { DESKTOP } from './helpers/player-page.js'

const LIMIT = 3

let server
let chromium
// The browser and inject() both come from 127.0.0.1: one address, one budget.
serverAndChromium({ env: { AUTH_FAILURE_LIMIT: String(LIMIT), AUTH_BLOCK_MS: '600000' } }, (started) => ({ server, chromium } = started))

/** Every console line of the page: errors and uncaught exceptions (page.problems), and warnings. */
const consoleLines = (page) => [...page.problems, ...page.warnings.map((text) => `console.warning: ${text}`)]

/** Signs in with `token` and returns the page's answer (the message is emptied first, so the wait is for this attempt's). */
async function signInWith (page, token) {
  await page.evaluate(() => { document.querySelector('#login-message').textContent = '' })
  await page.fill('#token', token)
  await page.click('#sign-in')
  await waitInPage(page, 'the answer to the sign-in', () => document.querySelector('#login-message').textContent !== '')
  return page.textContent('#login-message')
}

describe('operator sign-in', () => {
  it('shows a wrong token as a message with a clean console, signs in with the right one, and says how long to wait once the address is blocked', async () => {
    const page = await chromium.newPage({ viewport: DESKTOP })
    await page.goto(`${server.base}/audit`)
    await waitInPage(page, 'the audit page', () => window.__audit !== undefined)

    expect(await signInWith(page, 'x'.repeat(32))).toBe('That is not the operator token.')
    expect(await page.evaluate(() => window.__audit.signedIn)).toBe(false)
    expect(await page.evaluate(() => sessionStorage.getItem('plinko.operatorToken'))).toBe(null)
    expect(consoleLines(page)).toEqual([])

    // The right token: signed in, and the audit routes answer (an unknown drop is looked up in the list: a 200).
    expect(await signInWith(page, OPERATOR_TOKEN)).toBe('Signed in.')
    expect(await page.evaluate(() => window.__audit.signedIn)).toBe(true)
    await page.fill('#drop-id', '999999')
    await page.click('#id-form button')
    await waitInPage(page, 'the look-up', () => document.querySelector('#lookup-message').dataset.kind === 'error')
    expect(await page.textContent('#lookup-message')).toBe('Drop #999999: no drop 999999 is recorded.')
    await page.click('#sign-out')

    // Two more wrong tokens make LIMIT: the address is blocked, the next attempt (the right token too) is told so.
    for (let i = 1; i < LIMIT; i++) expect(await signInWith(page, `wrong-operator-token-${i}`)).toBe('That is not the operator token.')
    const blocked = await signInWith(page, OPERATOR_TOKEN)
    expect(blocked).toMatch(/^Too many wrong tokens from this address: try again in \d+ s\.$/)
    expect(Number(/in (\d+) s/.exec(blocked)[1])).toBeGreaterThan(500)
    expect(await page.evaluate(() => window.__audit.signedIn)).toBe(false)
    expect(consoleLines(page)).toEqual([])

    // The page's wrong tokens were counted: the audit routes refuse this address, whatever the token.
    const refused = await server.api('GET', '/api/audit/drops?limit=1', { token: OPERATOR_TOKEN })
    expect([refused.status, refused.body.code]).toEqual([429, 'E_RATE_LIMITED'])
    expect(Number(refused.headers['retry-after'])).toBeGreaterThan(500)
    await page.context().close()
  })
})
