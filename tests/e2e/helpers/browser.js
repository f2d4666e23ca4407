import { existsSync } from 'node:fs'
import { chromium } from 'playwright-core'
import { CHROMIUM_PATH, CHROMIUM_ARGS } from '../../../tools/chromium.js'

export { CHROMIUM_PATH, CHROMIUM_ARGS }

/**
 * Waits (up to `timeoutMs`) for the Chromium binary: on a fresh machine
 * CI may still be installing it.
 */
export async function waitForChromium (timeoutMs = 300_000) {
  const deadline = Date.now() + timeoutMs
  while (!existsSync(CHROMIUM_PATH)) {
    if (Date.now() > deadline) {
      throw new Error(`Chromium not found at ${CHROMIUM_PATH}: install Debian's package (apt-get install chromium) or set CHROMIUM_PATH. The e2e tests never download a browser.`)
    }
    await new Promise((resolve) => setTimeout(resolve, 2000))
  }
}

/**
 * Launches headless Chromium. playwright's launch() gives the browser a
 * fresh temporary profile (user-data dir) of its own and deletes it on close.
 */
export async function launchChromium () {
  await waitForChromium()
  const browser = await chromium.launch({ executablePath: CHROMIUM_PATH, headless: true, args: CHROMIUM_ARGS })
  return {
    browser,
    /**
     * A page in a context of its own (its own localStorage), its console watched.
     * @param {object} [options] browser.newContext options (viewport, isMobile, …)
     * @returns {Promise<import('playwright-core').Page & { problems: string[], warnings: string[] }>}
     */
    async newPage (options = {}) {
      const context = await browser.newContext(options)
      const page = await context.newPage()
      watchConsole(page)
      return page
    },
    async close () {
      await browser.close().catch(() => {})
    }
  }
}

/**
 * Records the page's console errors and uncaught exceptions on
 * `page.problems` (console warnings on `page.warnings`).
 * @param {import('playwright-core').Page} page
 */
export function watchConsole (page) {
  page.problems = []
  page.warnings = []
  page.on('console', (message) => {
    if (message.type() === 'error') page.problems.push(`console.error: ${message.text()} (${message.location()?.url ?? ''})`)
    else if (message.type() === 'warning') page.warnings.push(message.text())
  })
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`))
}

/**
 * Waits for `predicate` (a function run in the page) to return a truthy
 * value; the error names `what` and the page's problems so far.
 * @param {import('playwright-core').Page} page
 * @param {string} what
 * @param {Function} predicate
 * @param {any} [arg]
 * @param {number} [timeoutMs]
 */
export async function waitInPage (page, what, predicate, arg, timeoutMs = 90_000) {
  try {
    const handle = await page.waitForFunction(predicate, arg, { timeout: timeoutMs, polling: 100 })
    return await handle.jsonValue()
  } catch (error) {
    throw new Error(`timed out waiting for ${what}; page problems: ${JSON.stringify(page.problems ?? [])}\n${error.message}`)
  }
}
