/**
 * The player page in seeds mode (issue #23), in Chromium against the real
 * server: the page's socket gets no position frame at all, and every ball
 * the page draws is where the engine has it at that tick — to the bit,
 * for a late joiner's balls (fast-forwarded from `joined.balls`) and for
 * other players' drops whose frames reach the page 250 ms late (fast-
 * forwarded, never drawn at their start) — and every desync check agrees.
 * A man in the middle that forges the flight hash makes the page switch
 * the room to snapshots and report the desync (POST /api/client-errors).
 */
import { describe, it, expect, afterEach } from 'vitest'
import { createBoard, simulateDrop } from '../../engine/index.js'
import { SNAPSHOT_KIND, ROOM_FRAME_KIND } from '../../protocol/snapshot-codec.js'
import { DROP_EVENTS_KIND } from '../../protocol/drop-events-codec.js'
import { waitInPage } from './helpers/browser.js'
import { serverAndChromium } from './helpers/testbed.js'
import { openPlayer } from './helpers/player-page.js'
import { SETTLE_MARGIN_MS } from '../../client/room-clock.js'

const LATE_MS = 250

let server
let chromium
serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))

/** Pages opened by the running test, closed after it whether it passed or not. */
const opened = []
afterEach(async () => {
  for (const page of opened.splice(0)) await page.context().close().catch(() => {})
})

/**
 * Opens the page with its WebSocket routed through this process: binary
 * frames are counted by kind, and `alter(frame)` may hold one back (a
 * delay in ms) or change it before it goes on.
 */
async function openRouted ({ delayMs = 0, alter = (frame) => frame, query = '' } = {}) {
  const page = await chromium.newPage()
  const kinds = {}
  await page.routeWebSocket(/\/ws\?/, (ws) => {
    const upstream = ws.connectToServer()
    upstream.onMessage((message) => {
      if (typeof message === 'string') return ws.send(message)
      kinds[message[0]] = (kinds[message[0]] ?? 0) + 1
      const frame = alter(message)
      if (delayMs > 0) setTimeout(() => ws.send(frame), delayMs)
      else ws.send(frame)
    })
  })
  opened.push(page)
  await page.goto(`${server.base}/${query}`)
  await waitInPage(page, 'the page to join', () => window.__plinko?.ready === true)
  return { page, kinds }
}

/** Drops `count` balls from another player's page (auto-bet) and waits until the server has them all. */
async function dropFrom (page, count) {
  await page.fill('#auto-count', String(count))
  await page.click('#auto')
  await waitInPage(page, `${count} drops announced`, (n) => window.__plinko.history.length >= n, count)
}

/**
 * Every traced position against the engine: the drop's facts from the
 * ledger (the operator's audit route), its path from simulateDrop, the expected position the
 * engine's interpolation between the two steps around the traced tick.
 */
async function compareWithEngine (trace) {
  const paths = new Map()
  let compared = 0
  let worst = 0
  for (const { dropId, tick, x, y } of trace) {
    if (!paths.has(dropId)) {
      const { drop } = await server.audit(`/api/audit/drops/${dropId}`)
      const board = createBoard({ rows: drop.rows, risk: drop.risk, engineVersion: drop.engineVersion })
      paths.set(dropId, { startTick: drop.startTick, path: simulateDrop(board, drop.dropSeed, { trajectory: true }).trajectory })
    }
    const { startTick, path } = paths.get(dropId)
    const age = tick - startTick
    const i = Math.floor(age)
    const f = age - i
    const k = 3 * i
    const n = k + 3 < path.length ? k + 3 : k
    const ex = path[k] + (path[n] - path[k]) * f
    const ey = path[k + 1] + (path[n + 1] - path[k + 1]) * f
    worst = Math.max(worst, Math.abs(ex - x), Math.abs(ey - y))
    compared++
  }
  return { compared, worst, drops: paths.size }
}

describe('seeds delivery on the player page', () => {
  // The page simulates a seeds room in the board worker by default, on the main thread with ?simulation=main.
  it.each([
    ['in the board worker', '', 'worker'],
    ['on the main thread', '?simulation=main', 'main']
  ])("draws a late joiner's balls at the engine's positions, with no snapshot frame and every desync check agreeing (simulated %s)", async (where, query, simulatedIn) => {
    const dropper = await openPlayer(chromium, server)
    opened.push(dropper)
    expect(await dropper.evaluate(() => window.__plinko.delivery)).toBe('seeds')
    await dropFrom(dropper, 6)

    // Joins while those balls fall: they come in joined.balls and are fast-forwarded.
    const { page, kinds } = await openRouted({ query })
    await page.evaluate(() => window.__plinko.startSeedsTrace())
    expect(await page.evaluate(() => window.__plinko.simulatedIn)).toBe(simulatedIn)
    const joinedWith = await page.evaluate(() => window.__plinko.seeds.room.drops)
    expect(joinedWith).toBeGreaterThan(0)
    // The main thread's animation frames from here on: a room the worker simulates is drawn on the worker's own.
    await page.evaluate(() => {
      window.__animationFramesAsked = 0
      const ask = window.requestAnimationFrame.bind(window)
      window.requestAnimationFrame = (callback) => { window.__animationFramesAsked++; return ask(callback) }
    })
    // One more drop: its batch carries a desync check whatever the timing.
    await dropper.click('#drop')
    await waitInPage(page, 'the balls to land and a desync check', () => {
      const seeds = window.__plinko.seeds
      return seeds.room.checks > 0 && window.__plinko.lastFrame.balls === 0 && seeds.trace.length > 0
    })
    const seeds = await page.evaluate(() => window.__plinko.seeds)
    const animationFramesAsked = await page.evaluate(() => window.__animationFramesAsked)
    if (simulatedIn === 'worker') expect(animationFramesAsked).toBe(0)
    else expect(animationFramesAsked).toBeGreaterThan(30)
    const { compared, worst, drops } = await compareWithEngine(seeds.trace)
    console.info(`[e2e] late joiner (simulated ${where}): ${drops} drops, ${compared} drawn positions, largest difference from the engine ${worst} px; ${JSON.stringify(seeds.room)}; frames by kind ${JSON.stringify(kinds)}`)
    expect(compared).toBeGreaterThan(50)
    expect(worst).toBe(0)
    expect(seeds.room.fastForwarded).toBeGreaterThan(0)
    expect(seeds.room.mismatches).toBe(0)
    expect(seeds.desyncs).toEqual([])
    expect(seeds.otherFrames).toBe(0)
    expect(kinds[SNAPSHOT_KIND] ?? 0).toBe(0)
    expect(kinds[ROOM_FRAME_KIND] ?? 0).toBe(0)
    expect(kinds[DROP_EVENTS_KIND]).toBeGreaterThan(0)
    expect(page.problems).toEqual([])
  })

  it(`fast-forwards other players' drops whose frames arrive ${LATE_MS} ms late: never drawn at their start`, async () => {
    const { page, kinds } = await openRouted({ delayMs: LATE_MS })
    await page.evaluate(() => window.__plinko.startSeedsTrace())
    const dropper = await openPlayer(chromium, server)
    opened.push(dropper)
    await dropFrom(dropper, 5)
    const theirs = await dropper.evaluate(() => window.__plinko.history.map((h) => h.dropId))
    await waitInPage(page, "the other player's balls to land", (ids) => {
      const seeds = window.__plinko.seeds
      return ids.every((id) => seeds.trace.some((p) => p.dropId === id)) && seeds.room.inFlight === 0 && seeds.room.checks > 0
    }, theirs)
    const seeds = await page.evaluate(() => window.__plinko.seeds)
    const { compared, worst } = await compareWithEngine(seeds.trace)
    // The first tick each drop was drawn at: at least the frame's delay after its release, less the page's own margin.
    const first = new Map()
    for (const p of seeds.trace) if (theirs.includes(p.dropId) && !first.has(p.dropId)) first.set(p.dropId, p)
    const ages = []
    for (const [dropId, p] of first) ages.push(p.tick - (await server.audit(`/api/audit/drops/${dropId}`)).drop.startTick)
    console.info(`[e2e] late frames: first drawn at ages ${ages.map((a) => a.toFixed(1)).join(', ')} ticks; ${compared} positions, largest difference ${worst} px; ${JSON.stringify(seeds.room)}`)
    expect(ages).toHaveLength(5)
    for (const age of ages) expect(age).toBeGreaterThanOrEqual((LATE_MS - SETTLE_MARGIN_MS) * 60 / 1000 - 1)
    expect(seeds.room.fastForwarded).toBeGreaterThanOrEqual(5)
    expect(worst).toBe(0)
    expect(seeds.room.mismatches).toBe(0)
    expect(kinds[SNAPSHOT_KIND] ?? 0).toBe(0)
  })

  it('switches the room to snapshots and reports it when the flight hash is forged', async () => {
    let forged = 0
    const { page, kinds } = await openRouted({
      alter (frame) {
        if (frame[0] !== DROP_EVENTS_KIND || forged > 0) return frame
        forged++
        const copy = Buffer.from(frame)
        copy[5] ^= 1 // the hash's first word
        return copy
      }
    })
    const report = page.waitForRequest((request) => request.url().endsWith('/api/client-errors') && request.method() === 'POST')
    const dropper = await openPlayer(chromium, server)
    opened.push(dropper)
    await dropFrom(dropper, 3)
    const request = await report
    const body = request.postDataJSON()
    expect((await request.response()).status()).toBe(202)
    await waitInPage(page, 'the room shown from snapshots', () => window.__plinko.delivery === 'snapshots' && window.__plinko.snapshotChecks.positions > 0)
    const seeds = await page.evaluate(() => window.__plinko.seeds)
    expect(forged).toBe(1)
    expect(seeds.desyncs).toHaveLength(1)
    const [desync] = seeds.desyncs
    expect(body).toMatchObject({ code: 'E_DESYNC', room: '16-medium', tick: desync.tick, serverHash: desync.server, localHash: desync.local, page: 'player' })
    expect(body.serverHash).not.toBe(body.localHash)
    // Drawn from snapshots now: position frames arrive, and the balls still verify.
    expect((kinds[SNAPSHOT_KIND] ?? 0) + (kinds[ROOM_FRAME_KIND] ?? 0)).toBeGreaterThan(0)
    expect(await page.evaluate(() => window.__plinko.snapshotChecks.mismatches)).toBe(0)
    expect(await page.evaluate(() => window.__plinko.warnings)).toEqual([])
  })

  it("keeps a quiet room's clock from the heartbeats' pongs, which name the room's tick", async () => {
    const { page, kinds } = await openRouted()
    const framesBefore = kinds[DROP_EVENTS_KIND] ?? 0
    const before = await page.evaluate(() => window.__plinko.timeline.observations)
    // More samples than drop-events frames (the only other source after joined): a pong (every 5 s) named the tick.
    const deadline = Date.now() + 30_000
    let fromPongs = 0
    while (fromPongs < 1 && Date.now() < deadline) {
      await new Promise((resolve) => setTimeout(resolve, 250))
      const observations = await page.evaluate(() => window.__plinko.timeline.observations)
      fromPongs = (observations - before) - ((kinds[DROP_EVENTS_KIND] ?? 0) - framesBefore)
    }
    expect(fromPongs).toBeGreaterThanOrEqual(1)
    expect(await page.evaluate(() => window.__plinko.warnings)).toEqual([])
  })
})
