import { mkdirSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { createBoard, simulateDrop, deriveDropSeed } from '../../../engine/index.js'
import { waitInPage } from './browser.js'
import { DROP_EVENTS_KIND, DROP_EVENTS_HEADER_BYTES, DROP_EVENT_BYTES, decodeDropEvents, withOwnMessages } from '../../../protocol/drop-events-codec.js'
import { imageStats } from './png.js'

/**
 * What the player-page tests share: opening the page, screenshots at the
 * two sizes the issue names (1366×800 and 390×844) checked as not blank,
 * and outcomes chosen ahead: the test reads the player's active server
 * seed from the in-process server and picks a client seed whose next drop
 * lands where the test needs it (the page then plays and verifies that
 * drop like any other).
 */

export const SCREENSHOTS = join(tmpdir(), 'plinko-e2e-screenshots')
export const DESKTOP = { width: 1366, height: 800 }
export const PHONE = { width: 390, height: 844 }

/**
 * Opens the player page in a fresh context and waits for it to join its room.
 * @param {{ newPage: Function }} chromium @param {{ base: string }} server
 * @param {object} [options] context options, and `path`: the page's address (default `/`, e.g. `/?delivery=snapshots`)
 */
export async function openPlayer (chromium, server, { path = '/', ...options } = {}) {
  const page = await chromium.newPage({ viewport: DESKTOP, ...options })
  await page.goto(`${server.base}${path}`)
  await waitInPage(page, 'the page to join its room', () => window.__plinko?.ready === true)
  return page
}

/**
 * Screenshots the page at 1366×800 and at 390×844 (full page), saves them
 * and returns what is on each; the viewport is put back afterwards.
 * @param {import('playwright-core').Page} page @param {string} name
 */
export async function screenshotBoth (page, name) {
  mkdirSync(SCREENSHOTS, { recursive: true })
  const before = page.viewportSize()
  const shots = {}
  for (const [size, viewport] of [['desktop', DESKTOP], ['phone', PHONE]]) {
    await page.setViewportSize(viewport)
    // Two frames: the board is resized on the frame after a resize.
    await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))))
    const png = await page.screenshot({ fullPage: true })
    const file = join(SCREENSHOTS, `${name}-${size}.png`)
    writeFileSync(file, png)
    shots[size] = imageStats(png)
  }
  if (before) await page.setViewportSize(before)
  return shots
}

/** Asserts both screenshots show a drawn page (many colours, not one flat background). */
export function expectNotBlank (expect, shots) {
  for (const [size, stats] of Object.entries(shots)) {
    expect(stats.distinctColors, `${size} screenshot colours`).toBeGreaterThan(50)
    expect(stats.nonBackgroundShare, `${size} screenshot content`).toBeGreaterThan(0.15)
  }
}

/** The player's active server seed, read from the in-process server (tests only: it is never sent to a client). */
export async function activeServerSeed (server, playerId) {
  const accounts = server.arena.accounts
  const account = await accounts.acquire(playerId)
  try {
    return { serverSeed: account.seed.seed, nextNonce: account.seed.nextNonce }
  } finally {
    accounts.release(account)
  }
}

/**
 * A client seed whose drop number `nonce` under `serverSeed` lands in a
 * bucket whose multiplier satisfies `wanted`, on the newest engine's board.
 * @param {{ serverSeed: string, nonce: number, rows: number, risk: string, wanted: (multiplier: number) => boolean }} options
 */
export async function clientSeedFor ({ serverSeed, nonce, rows, risk, wanted }) {
  const board = createBoard({ rows, risk })
  for (let i = 0; i < 200_000; i++) {
    const clientSeed = `pick-${i}`
    const outcome = simulateDrop(board, await deriveDropSeed(serverSeed, clientSeed, nonce))
    if (wanted(outcome.multiplier)) return { clientSeed, ...outcome }
  }
  throw new Error('no client seed found')
}

/** Sets the client seed through the page's fairness panel and waits for the server's answer. */
export async function setClientSeed (page, clientSeed) {
  await page.fill('#client-seed', clientSeed)
  await page.click('#client-seed-form button')
  await waitInPage(page, 'the client seed to be set', (seed) => document.querySelector('#message').textContent.includes(seed), clientSeed)
}

/**
 * Distinct colours and bright pixels read back from a canvas (device px):
 * the board's from where it is drawn (window.__plinko.boardPixels: the
 * worker's OffscreenCanvas, which the page itself cannot read), any other
 * canvas's with getImageData.
 */
export function canvasStats (page, selector = '#board') {
  return page.evaluate(async (selector) => {
    const canvas = document.querySelector(selector)
    const { width, height, data } = selector === '#board'
      ? await window.__plinko.boardPixels()
      : { width: canvas.width, height: canvas.height, data: canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data }
    const colors = new Set()
    let bright = 0
    for (let i = 0; i < data.length; i += 4) {
      colors.add((data[i] << 16) | (data[i + 1] << 8) | data[i + 2])
      if (data[i] + data[i + 1] + data[i + 2] > 600) bright++
    }
    return { width, height, colors: colors.size, bright }
  }, selector)
}

/**
 * A man in the middle: alters the final state hash in the player's own
 * `settled` messages (not the room's `events`, which carry settled events
 * inside), all of them or only the first. @param {import('playwright-core').Page} page
 */
export function tamperSettledStateHash (page, { once = false } = {}) {
  let tampered = false
  return page.routeWebSocket(/\/ws\?/, (ws) => {
    const upstream = ws.connectToServer()
    const flip = (settled) => {
      tampered = true
      settled.stateHash = settled.stateHash.replace(/^./, (c) => (c === '0' ? '1' : '0'))
      return settled
    }
    upstream.onMessage((message) => {
      if (!(once && tampered) && typeof message === 'string' && message.startsWith('{"type":"settled"')) {
        message = JSON.stringify(flip(JSON.parse(message)))
      } else if (!(once && tampered) && typeof message !== 'string' && message[0] === DROP_EVENTS_KIND) {
        // Seeds mode: the player's own `settled` rides in the owner's section of a drop-events frame.
        const frame = decodeDropEvents(message)
        if (frame?.own.some((m) => m.type === 'settled')) {
          const own = frame.own.map((m) => JSON.stringify(m.type === 'settled' && !(once && tampered) ? flip(m) : m))
          message = Buffer.from(withOwnMessages(message.subarray(0, DROP_EVENTS_HEADER_BYTES + DROP_EVENT_BYTES * frame.events.length), own))
        }
      }
      ws.send(message)
    })
  })
}
