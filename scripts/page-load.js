#!/usr/bin/env node
/**
 * How fast the player page comes up: `node scripts/page-load.js [--runs 3]`.
 *
 * Starts the real server (SQLite in a temporary folder) and loads `/` in
 * headless Chromium (CHROMIUM_PATH, default /usr/bin/chromium) at
 * 1366×800, on loopback and on a throttled link (300 ms round trip,
 * 1.6 Mbps down, 750 kbps up: Chrome DevTools' "Slow 4G"-like profile the
 * issue names), each from a cold cache, and prints first paint, the first
 * frame with the board drawn, when the room was joined (session, socket,
 * `joined`), requests and bytes over the wire. Figures go to the README's player section.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { chromium } from 'playwright-core'
import { startServerProcess } from '../tools/server-process.js'
import { LIFTED_LIMITS } from '../tools/lifted-limits.js'
import { CHROMIUM_PATH, CHROMIUM_ARGS } from '../tools/chromium.js'

const { values } = parseArgs({ options: { runs: { type: 'string', default: '3' } } })
const RUNS = Number(values.runs)
const LINKS = [
  { name: 'loopback', conditions: null },
  { name: '300 ms / 1.6 Mbps', conditions: { offline: false, latency: 300, downloadThroughput: 1.6e6 / 8, uploadThroughput: 750e3 / 8 } }
]

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-page-load-'))
const server = startServerProcess(`sqlite:${path.join(dir, 'ledger.sqlite')}`, { ...LIFTED_LIMITS })
const browser = await chromium.launch({ executablePath: CHROMIUM_PATH, headless: true, args: CHROMIUM_ARGS })
try {
  const port = await server.port
  const rows = []
  for (const link of LINKS) {
    const samples = []
    for (let run = 0; run < RUNS; run++) samples.push(await loadOnce(`http://127.0.0.1:${port}/`, link.conditions))
    const median = (key) => samples.map((s) => s[key]).sort((a, b) => a - b)[Math.floor(samples.length / 2)]
    rows.push([link.name, median('firstPaint'), median('boardFrame'), median('joined'), median('requests'), median('bytes')])
  }
  console.log(`player page load, headless Chromium 1366×800, cold cache, median of ${RUNS}`)
  console.log('link                first paint  first board frame  room joined  requests  bytes on the wire')
  for (const [name, paint, frame, joined, requests, bytes] of rows) {
    console.log(`${name.padEnd(18)}  ${`${Math.round(paint)} ms`.padStart(11)}  ${`${Math.round(frame)} ms`.padStart(17)}  ${`${Math.round(joined)} ms`.padStart(11)}  ${String(requests).padStart(8)}  ${`${(bytes / 1024).toFixed(0)} KB`.padStart(17)}`)
  }
} finally {
  await browser.close()
  server.child.kill('SIGTERM')
  await server.exited
  fs.rmSync(dir, { recursive: true, force: true })
}

async function loadOnce (url, conditions) {
  const context = await browser.newContext({ viewport: { width: 1366, height: 800 } })
  const page = await context.newPage()
  const cdp = await context.newCDPSession(page)
  await cdp.send('Network.enable')
  await cdp.send('Network.setCacheDisabled', { cacheDisabled: true })
  if (conditions) await cdp.send('Network.emulateNetworkConditions', conditions)
  let requests = 0
  let bytes = 0
  cdp.on('Network.loadingFinished', (event) => { requests++; bytes += event.encodedDataLength })
  await page.goto(url, { waitUntil: 'commit' })
  await page.waitForFunction(() => window.__plinko?.ready === true, null, { timeout: 60_000, polling: 'raf' })
  const timing = await page.evaluate(() => {
    const paint = performance.getEntriesByName('first-paint')[0]
    return { firstPaint: paint ? paint.startTime : NaN, boardFrame: window.__plinko.firstBoardFrameAt, joined: performance.now() }
  })
  await context.close()
  return { ...timing, requests, bytes }
}
