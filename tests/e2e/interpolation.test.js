/**
 * Rendering under a bad network (issue #4): the page's snapshot frames are
 * held back by random delays of up to 150 ms on their way from the server
 * (through playwright's WebSocket routing), so they arrive late, bunched
 * and out of order. The page must adapt its playout buffer to the jitter,
 * drop the snapshots that arrive too late, and keep every ball moving
 * smoothly: the render clock only ever moves forward, never snaps, and
 * every ball is drawn within half a pixel of where the engine's
 * simulation has it at that tick — no teleporting, no stutter.
 */
import { describe, it, expect } from 'vitest'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'

const MAX_FRAME_DELAY_MS = 150
const DROPS = 8

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

/** A small seeded generator, so a failing run can be repeated. */
function lcg (seed) {
  let state = seed >>> 0
  return () => {
    state = (Math.imul(state, 1664525) + 1013904223) >>> 0
    return state / 2 ** 32
  }
}

describe('snapshot interpolation', () => {
  it('stays smooth and exact when snapshots arrive late and out of order', async () => {
    const page = await chromium.newPage({ viewport: { width: 1000, height: 900 } })
    const random = lcg(20240611)
    let delayed = 0
    await page.routeWebSocket(/\/ws\?/, (ws) => {
      const upstream = ws.connectToServer()
      upstream.onMessage((message) => {
        if (typeof message === 'string') {
          ws.send(message)
          return
        }
        delayed++
        setTimeout(() => ws.send(message), random() * MAX_FRAME_DELAY_MS)
      })
    })
    await page.goto(`${server.base}/?delivery=snapshots`)
    await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
    await page.evaluate(() => window.__plinko.startTrace())
    await page.fill('#auto-count', String(DROPS))
    await page.click('#auto')
    await waitInPage(page, `${DROPS} verifications`, (n) => window.__plinko.verifications.length >= n, DROPS, 120_000)

    const { trace, timeline, verifications, snapshotChecks } = await page.evaluate(() => ({
      trace: window.__plinko.trace,
      timeline: window.__plinko.timeline,
      verifications: window.__plinko.verifications,
      snapshotChecks: window.__plinko.snapshotChecks
    }))
    const maxDeviation = Math.max(...trace.map((f) => f.deviation))
    console.info(`[e2e] ${delayed} snapshot frames delayed; timeline ${JSON.stringify(timeline)}; ${trace.length} frames traced, largest distance from the simulated path ${maxDeviation.toFixed(3)} px`)

    expect(verifications.every((v) => v.verified)).toBe(true)
    expect(snapshotChecks.mismatches).toBe(0)

    // The bad network happened, and the page adapted to it.
    expect(delayed).toBeGreaterThan(20)
    expect(timeline.outOfOrder + timeline.stale).toBeGreaterThan(0)
    expect(timeline.jitterMs).toBeGreaterThan(5)
    expect(timeline.delayMs).toBeGreaterThan(100)

    // No teleport, no stutter: time moves forward every frame and never jumps,
    // and every ball is where the simulation says (snapshots are 0.5 px steps: ≤ 0.25 px per axis).
    expect(timeline.snaps).toBe(0)
    expect(trace.length).toBeGreaterThan(60)
    for (let i = 1; i < trace.length; i++) {
      if (trace[i].now > trace[i - 1].now) expect(trace[i].tick, `frame ${i}`).toBeGreaterThan(trace[i - 1].tick)
    }
    expect(maxDeviation).toBeLessThanOrEqual(Math.SQRT1_2 * 0.5 + 1e-6)
    expect(page.problems).toEqual([])
    await page.context().close()
  })
})
