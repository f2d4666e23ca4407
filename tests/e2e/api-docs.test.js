import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'

/**
 * /docs (Swagger UI) and /docs/websocket under the app's real
 * Content-Security-Policy (helmet, server/app.js): the page renders every
 * operation of /api/openapi.json, a request sent from it ("Try it out")
 * reaches the server, and Chromium reports no CSP violation or error.
 */
describe('API description pages in Chromium', () => {
  let server
  let chromium
  serverAndChromium({}, (started) => ({ server, chromium } = started))

  /** A page that records CSP violations (securitypolicyviolation events) as they happen. */
  async function openPage (path) {
    const page = await chromium.newPage()
    page.violations = []
    await page.exposeFunction('reportViolation', (text) => page.violations.push(text))
    await page.addInitScript(() => {
      document.addEventListener('securitypolicyviolation', (event) => window.reportViolation(`${event.violatedDirective} ${event.blockedURI}`))
    })
    const response = await page.goto(`${server.base}${path}`)
    expect(response.status()).toBe(200)
    expect(response.headers()['content-security-policy']).toContain("script-src 'self'")
    return page
  }

  it('/docs renders every operation of the OpenAPI document, and Try it out reaches the server', async () => {
    const document = (await server.api('GET', '/api/openapi.json')).body
    const operations = Object.values(document.paths).reduce((n, methods) => n + Object.keys(methods).length, 0)
    const page = await openPage('/docs')
    const rendered = await waitInPage(page, 'Swagger UI to render the operations', (expected) => {
      const count = document.querySelectorAll('.opblock').length
      return count >= expected && count
    }, operations, 30_000)
    expect(rendered).toBe(operations)
    expect(await page.textContent('.info .title')).toContain('Plinko Arena HTTP API')

    // Try it out on GET /api/health: the UI's fetch passes connect-src and gets the real answer.
    const health = page.locator('.opblock-get', { hasText: '/api/health' }).first()
    await health.locator('.opblock-summary').click()
    await health.locator('button.try-out__btn').click()
    await health.locator('button.execute').click()
    const body = await waitInPage(page, 'the health response', () => document.querySelector('.opblock-get .live-responses-table .response-col_description .microlight')?.textContent, undefined, 15_000)
    expect(JSON.parse(body)).toMatchObject({ status: 'ok', engineVersion: expect.any(String) })
    expect(page.violations).toEqual([])
    expect(page.problems).toEqual([])
  })

  it('/docs/websocket lists every client message and server message under the same policy', async () => {
    const protocol = (await server.api('GET', '/api/asyncapi.json')).body
    const page = await openPage('/docs/websocket')
    const sections = await page.$$eval('section[id]', (nodes) => nodes.map((node) => node.id))
    expect(sections.sort()).toEqual(Object.keys(protocol.channels.game.messages).sort())
    expect(page.violations).toEqual([])
    expect(page.problems).toEqual([])
  })
})
