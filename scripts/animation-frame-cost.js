#!/usr/bin/env node
/**
 * What an animation frame costs the player page's main thread when it
 * changes nothing: `node scripts/animation-frame-cost.js [--seconds 6] [--throttle 4]`.
 *
 * Starts the real server (SQLite in a temporary folder), opens the player
 * page in headless Chromium (CHROMIUM_PATH) at 1366×800 with the CPU
 * slowed `--throttle` times, in a room where nothing falls, and reads the
 * main thread's task time (CDP Performance.getMetrics TaskDuration) over a
 * window, three ways: the page as it is; the same page with
 * requestAnimationFrame answering a callback that does nothing (only the
 * browser's frame lifecycle is left); and with no animation frame asked
 * for at all. This is why a seeds room simulated in the board worker is
 * drawn on the worker's own animation frames (client/board-worker-room.js):
 * a frame asked for on the main thread costs it its rendering lifecycle
 * (style, layout, paint, commit) even when nothing on the page changes.
 * Figures go to docs/client.md.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { chromium } from 'playwright-core'
import { startServerProcess } from '../tools/server-process.js'
import { LIFTED_LIMITS } from '../tools/lifted-limits.js'
import { CHROMIUM_PATH, CHROMIUM_ARGS } from '../tools/chromium.js'

const { values } = parseArgs({ options: { seconds: { type: 'string', default: '6' }, throttle: { type: 'string', default: '4' } } })
const SECONDS = Number(values.seconds)
const THROTTLE = Number(values.throttle)
if (!(SECONDS > 0) || !(THROTTLE >= 1)) throw new Error('usage: node scripts/animation-frame-cost.js [--seconds S > 0] [--throttle R >= 1]')

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-animation-frame-'))
const server = startServerProcess(`sqlite:${path.join(dir, 'ledger.sqlite')}`, { ...LIFTED_LIMITS })
const browser = await chromium.launch({ executablePath: CHROMIUM_PATH, headless: true, args: [...CHROMIUM_ARGS] })
const rows = []
try {
  const base = `http://127.0.0.1:${await server.port}`
  const context = await browser.newContext({ viewport: { width: 1366, height: 800 } })
  const page = await context.newPage()
  await page.goto(`${base}/?delivery=seeds`)
  await page.waitForFunction(() => window.__plinko?.ready === true, null, { timeout: 60_000 })
  const cdp = await context.newCDPSession(page)
  await cdp.send('Performance.enable')
  await cdp.send('Emulation.setCPUThrottlingRate', { rate: THROTTLE })
  const ways = [
    ['the page as it is (its render loop parked: the room is simulated in the worker)', null],
    ['an animation frame every frame, its callback doing nothing', () => {
      const loop = () => requestAnimationFrame(loop)
      requestAnimationFrame(loop)
    }],
    ['no animation frame asked for', () => {
      window.requestAnimationFrame = () => 0
    }]
  ]
  for (const [label, change] of ways) {
    if (change) await page.evaluate(change)
    await new Promise((resolve) => setTimeout(resolve, 2000))
    const before = await taskSeconds(cdp)
    const started = performance.now()
    const framesBefore = await page.evaluate(() => window.__plinko.frames)
    await new Promise((resolve) => setTimeout(resolve, SECONDS * 1000))
    const seconds = (performance.now() - started) / 1000
    rows.push({ label, msPerSecond: (await taskSeconds(cdp) - before) * 1000 / seconds, drawn: (await page.evaluate(() => window.__plinko.frames)) - framesBefore })
  }
  await context.close()
} finally {
  await browser.close()
  server.child.kill('SIGTERM')
  await server.exited
  fs.rmSync(dir, { recursive: true, force: true })
}

console.log(`player page at 1366×800, nothing falling, headless Chromium, CPU throttled ${THROTTLE}×, ${SECONDS} s windows`)
console.log('main thread ms per second  board frames drawn  what the page does')
for (const r of rows) console.log(`${r.msPerSecond.toFixed(1).padStart(25)}  ${String(r.drawn).padStart(18)}  ${r.label}`)

async function taskSeconds (cdp) {
  const { metrics } = await cdp.send('Performance.getMetrics')
  return metrics.find((m) => m.name === 'TaskDuration').value
}
