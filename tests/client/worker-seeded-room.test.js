/**
 * A seeds room simulated in the board worker (client/board-worker-room.js)
 * as the page sees it (client/worker-seeded-room.js), in Node with the real
 * engine: the worker's side is run in-process behind a stand-in for the
 * WorkerBoard that hands messages over as the real one does (one frame's
 * report after the frame). What the page hears must be what a SeededRoom on
 * the main thread would have told it: the same landings and outcomes, the
 * same peg contacts, the same flight hash, the same packed positions.
 */
import { describe, it, expect } from 'vitest'
import { createBoard, simulateDrop } from '../../engine/index.js'
import { WorkerRoom } from '../../client/board-worker-room.js'
import { WorkerSeededRoom } from '../../client/worker-seeded-room.js'
import { SeededRoom } from '../../client/seeded-room.js'
import { packPoses, poseBuffer, STRIDE } from '../../client/pose-frame.js'

const board = createBoard({ rows: 12, risk: 'medium' })
const seed = (i) => (i * 2654435761 >>> 0).toString(16).padStart(8, '0').repeat(8)
const drop = (i, startTick, mine = false) => ({ dropId: 200 + i, player: mine ? 'me' : 'other', mine, room: '12-medium', rows: 12, risk: 'medium', engineVersion: board.engineVersion, dropSeed: seed(i), startTick, slot: i, bet: 10, bucket: null, ticks: null, stateHash: null, trajectory: null })

/** The WorkerBoard's seeds methods, with the worker's side run here (structuredClone: what postMessage copies). */
class InProcessWorkerBoard {
  constructor () { this.room = null; this.onReport = null; this.generation = 0; this.frames = [] }
  openSeedsRoom (spec, onReport) { this.generation++; this.onReport = onReport; this.room = new WorkerRoom(structuredClone(spec)) }
  closeSeedsRoom () { this.room = null; this.onReport = null }
  seedsAdd (d) { this.room?.add(structuredClone(d)) }
  seedsComplete (dropId) { this.room?.complete(dropId) }
  seedsTrace (on) { this.room?.trace(on) }
  seedsCheck (tick, hash) { return Promise.resolve(this.room ? structuredClone(this.room.check(tick, hash)) : null) }
  seedsFrame (tick) {
    const { poses, count, report } = this.room.frame(tick)
    this.frames.push(poses.slice(0, count * STRIDE))
    this.onReport(structuredClone(report))
  }
}

describe('a seeds room simulated in the board worker', () => {
  it('tells the page the landings, outcomes, peg contacts and flight hashes a main-thread SeededRoom gives, and draws the same positions', async () => {
    const worker = new InProcessWorkerBoard()
    const page = new WorkerSeededRoom({ room: '12-medium', board, boardOf: { rows: 12, risk: 'medium' }, worker })
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
      worker.seedsFrame(tick)
      const poses = local.posesAt(tick)
      const count = packPoses(poses, expected)
      expect(worker.frames.at(-1)).toEqual(expected.slice(0, count * STRIDE))
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
    const page = new WorkerSeededRoom({ room: '12-medium', board, boardOf: { rows: 12, risk: 'medium' }, worker })
    page.add(drop(7, 0, true))
    page.add(drop(8, 0))
    worker.seedsFrame(10)
    expect(page.ownInFlight).toBe(1)
    expect(page.balls).toBe(2)
    expect(page.mineDrawn).toBe(1)
    expect(await page.check(10, '0000000000000000')).toMatchObject({ ok: false, tick: 10, server: '0000000000000000', balls: 2 })
    // Its settlement came first: stepped to its landing in the worker, drawn as the clock gets there.
    page.complete(207)
    worker.seedsFrame(11)
    expect(page.balls).toBe(2)
    page.close()
    expect(await page.check(12, '0000000000000000')).toBe(null)
  })
})
