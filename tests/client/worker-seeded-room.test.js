/**
 * A seeds room simulated in the board worker (client/board-worker-room.js)
 * as the page sees it (client/worker-seeded-room.js), in Node with the real
 * engine: the worker's side is run in-process behind a stand-in for the
 * WorkerBoard that hands messages over as the real one does (a frame's
 * report after the frame), drawing on a stand-in painter. What the page
 * hears must be what a SeededRoom on the main thread would have told it:
 * the same landings and outcomes, the same peg contacts, the same flight
 * hash, the same packed positions; the worker starts the glows and pops,
 * reports only what happened (or its counters, every REPORT_EVERY_MS), and
 * stops asking for frames once nothing moves; its render tick follows the
 * line of the page's room clock as the page's own would.
 */
import { describe, it, expect } from 'vitest'
import { createBoard, simulateDrop } from '../../engine/index.js'
import { WorkerRoom, REPORT_EVERY_MS } from '../../client/board-worker-room.js'
import { WorkerSeededRoom } from '../../client/worker-seeded-room.js'
import { SeededRoom } from '../../client/seeded-room.js'
import { RoomClock, RenderTickFollower } from '../../client/room-clock.js'
import { packPoses, poseBuffer, STRIDE } from '../../client/pose-frame.js'

const board = createBoard({ rows: 12, risk: 'medium' })
const seed = (i) => (i * 2654435761 >>> 0).toString(16).padStart(8, '0').repeat(8)
const drop = (i, startTick, mine = false) => ({ dropId: 200 + i, player: mine ? 'me' : 'other', mine, room: '12-medium', rows: 12, risk: 'medium', engineVersion: board.engineVersion, dropSeed: seed(i), startTick, slot: i, bet: 10, bucket: null, ticks: null, stateHash: null, trajectory: null })

/** The painter's surface drive() uses: what it was told to start, and what it drew. */
class StandInPainter {
  constructor () { this.commands = []; this.drawn = []; this.animating = false }
  apply (command) { this.commands.push(command) }
  draw ({ poses, count }) { this.drawn.push(poses.slice(0, count * STRIDE)); return { trails: count, floaterClearance: null } }
}

/** The WorkerBoard's seeds methods, with the worker's side run here (structuredClone: what postMessage copies). */
class InProcessWorkerBoard {
  constructor () { this.room = null; this.onReport = null; this.painter = new StandInPainter(); this.lines = []; this.now = 0 }
  openSeedsRoom (spec, onReport) { this.onReport = onReport; this.room = new WorkerRoom(structuredClone(spec)) }
  closeSeedsRoom () { this.room = null; this.onReport = null }
  seedsClock (line) { this.lines.push(line); if (this.room) this.room.line = structuredClone(line) }
  seedsAdd (d) { this.room?.add(structuredClone(d)) }
  seedsComplete (dropId) { this.room?.complete(dropId) }
  seedsTrace (on) { this.room?.trace(on) }
  seedsCheck (tick, hash) { return Promise.resolve(this.room ? structuredClone(this.room.check(tick, hash)) : null) }
  /** One of the worker's frames at render tick `tick`, `elapsedMs` after the last. */
  frameAt (tick, { elapsedMs = REPORT_EVERY_MS, reducedMotion = false, changed = false } = {}) {
    this.now += elapsedMs
    const { report, moving } = this.room.drawFrame(this.painter, tick, this.now, { reducedMotion, changed })
    if (report) this.onReport(structuredClone(report))
    return { reported: report !== null, moving }
  }
}

const clock = () => new RoomClock({ tickRate: 60 })

describe('a seeds room simulated in the board worker', () => {
  it('tells the page the landings, outcomes, peg contacts and flight hashes a main-thread SeededRoom gives, and draws the same positions', async () => {
    const worker = new InProcessWorkerBoard()
    const page = new WorkerSeededRoom({ room: '12-medium', board, boardOf: { rows: 12, risk: 'medium' }, worker, clock: clock() })
    const local = new SeededRoom({ room: '12-medium', board })
    const drops = [drop(1, 5, true), drop(2, 9), drop(3, 40), drop(4, 41, true)]
    for (const d of drops) {
      page.add(d)
      local.add({ ...d })
    }
    page.add(drops[0]) // named again by a batch: once only
    expect(page.has(drops[1].dropId)).toBe(true)
    page.trace = []
    local.trace = []
    const heard = { page: [], local: [] }
    const hits = { page: 0, local: 0 }
    let checks = 0
    const expected = poseBuffer(8)
    for (let tick = 0; tick < 600; tick += 0.5) {
      worker.frameAt(tick)
      const poses = local.posesAt(tick)
      const count = packPoses(poses, expected)
      expect(worker.painter.drawn.at(-1)).toEqual(expected.slice(0, count * STRIDE))
      expect(page.balls).toBe(count)
      hits.page += page.pegHits.length; page.pegHits.length = 0
      hits.local += local.pegHits.length; local.pegHits.length = 0
      for (const l of page.landings) heard.page.push({ dropId: l.dropId, bucket: l.bucket, stale: l.stale, mine: l.mine })
      for (const l of local.landings) heard.local.push({ dropId: l.dropId, bucket: l.bucket, stale: l.stale, mine: l.mine })
      page.landings.length = 0
      local.landings.length = 0
      if (tick % 30 === 0) {
        const [there, here] = [await page.check(tick, local.flightHash(tick)), local.check(tick, local.flightHash(tick))]
        expect(there).toEqual(here)
        checks++
      }
    }
    expect(checks).toBe(20)
    expect(hits.page).toBeGreaterThan(20)
    expect(hits.page).toBe(hits.local)
    expect(heard.page).toEqual(heard.local)
    // The worker started a glow for each contact and a pop for each landing that was not stale.
    const started = (kind) => worker.painter.commands.filter((c) => c[0] === kind).length
    expect(started('glow')).toBe(hits.page)
    expect(started('flash')).toBe(heard.page.filter((l) => !l.stale).length)
    expect(heard.page.map((l) => l.dropId).sort()).toEqual(drops.map((d) => d.dropId).sort())
    // Each drop's outcome, filled in on the page's own record, is the engine's; another player's result is on it for the feed.
    for (const d of drops) {
      const outcome = simulateDrop(board, d.dropSeed)
      expect({ bucket: d.bucket, ticks: d.ticks, stateHash: d.stateHash }).toEqual({ bucket: outcome.bucket, ticks: outcome.ticks, stateHash: outcome.stateHash })
      // Reported, not shown: the render loop marks it shown when it plays the landing (a `settled` in between waits for that).
      expect(d.landingShown).not.toBe(true)
      if (!d.mine) expect(d.result).toMatchObject({ dropId: d.dropId, multiplier: board.multipliers[outcome.bucket], bet: 10 })
    }
    // Every ball left the board (landed and faded): the page's drops are empty, as the worker's are.
    expect(page.drops.size).toBe(0)
    expect(page.ownInFlight).toBe(0)
    expect(page.trace).toEqual(local.trace)
    expect(page.stats).toMatchObject({ drops: 4, checks: 20, mismatches: 0, steps: local.stats.steps })
  })

  it('answers a forged hash as a mismatch, counts the player\'s balls in flight, and stops when closed', async () => {
    const worker = new InProcessWorkerBoard()
    const page = new WorkerSeededRoom({ room: '12-medium', board, boardOf: { rows: 12, risk: 'medium' }, worker, clock: clock() })
    page.add(drop(7, 0, true))
    page.add(drop(8, 0))
    worker.frameAt(10)
    expect(page.ownInFlight).toBe(1)
    expect(page.balls).toBe(2)
    expect(page.mineDrawn).toBe(1)
    expect(await page.check(10, '0000000000000000')).toMatchObject({ ok: false, tick: 10, server: '0000000000000000', balls: 2 })
    // Its settlement came first: stepped to its landing in the worker, drawn as the clock gets there.
    page.complete(207)
    worker.frameAt(11)
    expect(page.balls).toBe(2)
    let closed = 0
    page.onClose = () => closed++
    page.close()
    page.close()
    expect(closed).toBe(1)
    expect(await page.check(12, '0000000000000000')).toBe(null)
  })

  it('reports only what happened, or its counters every REPORT_EVERY_MS; skips still frames and stops when nothing moves; no effects with reduced motion', () => {
    const worker = new InProcessWorkerBoard()
    const page = new WorkerSeededRoom({ room: '12-medium', board, boardOf: { rows: 12, risk: 'medium' }, worker, clock: clock() })
    const reports = []
    page.onReport = (report) => reports.push(report)
    const flight = simulateDrop(board, seed(9))
    page.add(drop(9, 0))
    let frames = 0
    let reported = 0
    let tick = 0
    // Every frame a 60th of a second after the last, reduced motion: no glows, no pops.
    for (; tick <= flight.ticks + 200; tick++) {
      const frame = worker.frameAt(tick, { elapsedMs: 1000 / 60, reducedMotion: true })
      frames++
      if (frame.reported) reported++
      if (!frame.moving) break
    }
    expect(worker.painter.commands).toEqual([])
    expect(page.drops.size).toBe(0)
    // Fewer reports than frames: the frames with no contact, landing or retirement waited for their counters' turn.
    expect(reported).toBeLessThan(frames)
    expect(reports.reduce((sum, r) => sum + r.drawn.frames, 0)).toBe(worker.painter.drawn.length)
    expect(reports.reduce((sum, r) => sum + r.pegHits.length, 0)).toBeGreaterThan(0)
    expect(reports.every((r) => r.drawn.pegGlows === 0 && r.drawn.bucketPops === 0)).toBe(true)
    expect(reports.flatMap((r) => r.landings).map((l) => l.dropId)).toEqual([209])
    // Nothing moves any more: a still frame is drawn once, then none until something changes.
    const drawn = worker.painter.drawn.length
    expect(worker.frameAt(tick + 1)).toEqual({ reported: false, moving: false })
    expect(worker.painter.drawn.length).toBe(drawn)
    worker.frameAt(tick + 2, { changed: true })
    expect(worker.painter.drawn.length).toBe(drawn + 1)
  })

  it("sends the worker the room clock's line as it moves; the worker's render tick follows it as the page's RoomClock does", () => {
    const worker = new InProcessWorkerBoard()
    const roomClock = clock()
    roomClock.observe(100, 1000)
    const page = new WorkerSeededRoom({ room: '12-medium', board, boardOf: { rows: 12, risk: 'medium' }, worker, clock: roomClock })
    expect(worker.lines).toEqual([roomClock.line])
    const follower = new RenderTickFollower()
    for (let now = 1000; now < 3000; now += 16.7) {
      if (Math.round(now) % 250 < 17) roomClock.observe(Math.floor(100 + (now - 1000) * 0.06 + (now % 7)), now)
      expect(follower.advance(worker.room.line, now)).toBe(roomClock.advance(now))
    }
    expect(worker.lines.length).toBeGreaterThan(5)
    page.close()
    const sent = worker.lines.length
    roomClock.observe(500, 4000)
    expect(worker.lines.length).toBe(sent)
  })
})
