import { beforeAll, afterAll } from 'vitest'
import { startArenaServer } from './arena-server.js'
import { launchChromium } from './browser.js'

/**
 * The real server and Debian's Chromium for one e2e test file: started
 * before its tests, closed after them (the browser first). `use` gets
 * `{ server, chromium }` once both run (and may set up more: it is
 * awaited before the tests start), e.g.
 * `serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))`.
 * @param {Parameters<typeof startArenaServer>[0]} serverOptions
 * @param {(started: { server: any, chromium: any }) => void | Promise<void>} use
 */
export function serverAndChromium (serverOptions, use) {
  const started = { server: null, chromium: null }
  beforeAll(async () => {
    started.server = await startArenaServer(serverOptions)
    started.chromium = await launchChromium()
    await use(started)
  })
  afterAll(async () => {
    await started.chromium?.close()
    await started.server?.close()
  })
}
