/**
 * The seeds-mode page's pure parts, in Node with the real engine: every
 * ball drawn from its own fixed-step simulation is at the engine's state
 * at every whole tick (bit for bit) and at the engine's interpolation
 * between two; a drop added late is stepped to where it is before it is
 * first drawn; the landing is the engine's outcome; the flight hash is
 * the one a room computes over one shared simulator (as the server does);
 * and the room clock follows the room's tick from arrivals.
 */
import { describe, it, expect } from 'vitest'
import { createBoard, simulateDrop, DropSimulator } from '../../engine/index.js'
import { FlightHasher, encodeDropEvents } from '../../protocol/drop-events-codec.js'
import { encodeSnapshot } from '../../protocol/snapshot-codec.js'
import { applyDropEvents, applyPong, pageDelivery } from '../../client/seeds-delivery.js'
import { SnapshotTimeline } from '../../client/snapshot-timeline.js'
import { SeededRoom } from '../../client/seeded-room.js'
import { RoomClock, SETTLE_MARGIN_MS } from '../../client/room-clock.js'
import { DropVerifier } from '../../client/drop-verifier.js'

const board = createBoard({ rows: 12, risk: 'medium' })
const seed = (i) => (i * 2654435761 >>> 0).toString(16).padStart(8, '0').repeat(8)

function drop (i, startTick, slot = i) {
  return { dropId: 100 + i, player: 'b'.repeat(16), mine: false, room: '12-medium', engineVersion: board.engineVersion, dropSeed: seed(i), startTick, slot, bet: 5, bucket: null, ticks: null, stateHash: null, trajectory: null }
}

const lerp = (p, q, t) => p + (q - p) * t

describe('SeededRoom', () => {
  it('draws every ball at the engine state of (tick − start tick): exact at whole ticks, the engine interpolation between', () => {
    const room = new SeededRoom({ room: '12-medium', board })
    const drops = [drop(1, 10), drop(2, 14), drop(3, 31)]
    for (const d of drops) room.add(d)
    const engine = drops.map((d) => simulateDrop(board, d.dropSeed, { trajectory: true }).trajectory)
    let compared = 0
    for (let tick = 10; tick < 200; tick += 0.25) {
      const poses = room.posesAt(tick)
      for (const pose of poses) {
        if (pose.trajectory === null) continue // landed, fading in its bucket
        const i = drops.findIndex((d) => d.dropId === pose.dropId)
        const age = tick - drops[i].startTick
        const k = 3 * Math.floor(age)
        const f = age - Math.floor(age)
        const t = engine[i]
        expect(pose.x).toBe(f === 0 ? t[k] : lerp(t[k], t[k + 3], f))
        expect(pose.y).toBe(f === 0 ? t[k + 1] : lerp(t[k + 1], t[k + 4], f))
        compared++
      }
    }
    expect(compared).toBeGreaterThan(1000)
    expect(room.stats.fastForwarded).toBe(0)
  })

  it('fast-forwards a drop that arrives late: first drawn where the engine has it, never at its start', () => {
    const room = new SeededRoom({ room: '12-medium', board })
    const late = drop(4, 100)
    room.posesAt(114.5) // the clock is 14.5 ticks past the drop's start before it is known
    room.add(late)
    const [pose] = room.posesAt(115)
    const t = simulateDrop(board, late.dropSeed, { trajectory: true }).trajectory
    expect([pose.x, pose.y]).toEqual([t[3 * 15], t[3 * 15 + 1]])
    expect(room.stats.fastForwarded).toBe(1)
    expect(room.stats.fastForwardSteps).toBe(15)
  })

  it('lands where the engine lands, reports the landing once, and a settlement can complete a ball ahead of the drawing', () => {
    const landed = []
    const room = new SeededRoom({ room: '12-medium', board, onLanded: (d) => landed.push(d.dropId) })
    const d = drop(5, 0)
    room.add(d)
    const outcome = simulateDrop(board, d.dropSeed)
    room.posesAt(10)
    room.complete(d.dropId)
    expect({ bucket: d.bucket, ticks: d.ticks, stateHash: d.stateHash }).toEqual({ bucket: outcome.bucket, ticks: outcome.ticks, stateHash: outcome.stateHash })
    expect(landed).toEqual([d.dropId])
    expect(room.posesAt(11)[0].trajectory).not.toBe(null) // still drawn in flight, at the clock
    expect(room.landings).toEqual([])
    room.posesAt(outcome.ticks + 1)
    room.posesAt(outcome.ticks + 2)
    expect(room.landings.map((l) => [l.dropId, l.bucket, l.stale])).toEqual([[d.dropId, outcome.bucket, false]])
    expect(d.result.multiplier).toBe(board.multipliers[outcome.bucket])
    room.posesAt(outcome.ticks + 100)
    expect(room.drops.size).toBe(0)
  })

  it("hashes the balls in flight as a room's single simulator does", () => {
    // The server's way: one DropSimulator, a ball's slot is its body id.
    const server = new DropSimulator(board)
    const starts = [0, 3, 3, 20, 45]
    const drops = []
    const page = new SeededRoom({ room: '12-medium', board })
    const hasher = new FlightHasher()
    for (let tick = 0; tick <= 140; tick++) {
      starts.forEach((start, i) => {
        if (start !== tick) return
        const d = drop(10 + i, tick, 0)
        d.slot = server.addDrop(d.dropSeed, d)
        drops.push(d)
        page.add(d)
      })
      if (tick % 7 === 0) {
        hasher.begin(tick)
        for (let slot = 0; slot < server.world.bodyCount; slot++) {
          if (server.ticksOf(slot) < 0) continue
          const w = server.world
          hasher.add(slot, w.xOf(slot), w.yOf(slot), w.vxOf(slot), w.vyOf(slot))
        }
        expect(page.check(tick, hasher.digest()).ok).toBe(true)
      }
      server.step()
    }
    expect(page.stats.checks).toBe(21)
    expect(page.check(140, '0123456789abcdef').ok).toBe(false)
  })
})

describe('a drop-events frame on the page', () => {
  it('sets the clock, puts only new drops on the board, checks the hash, and is told apart from any other frame', () => {
    const view = new SeededRoom({ room: '12-medium', board })
    const clock = new RoomClock({ tickRate: 60 })
    const known = drop(30, 0)
    view.add(known)
    const fresh = drop(31, 2, 1)
    const wire = (d) => ({ id: d.dropId, bet: d.bet, startTick: d.startTick, slot: d.slot, engineVersion: d.engineVersion, playerId: d.player, dropSeed: d.dropSeed })
    // The server's hash at tick 9 of both balls, from a page that knows both.
    const both = new SeededRoom({ room: '12-medium', board })
    both.add(drop(30, 0))
    both.add(drop(31, 2, 1))
    const hash = both.flightHash(9)
    const added = []
    const frame = encodeDropEvents(9, hash, [wire(known), wire(fresh)])
    const add = (event) => { added.push(event.dropId); view.add({ ...drop(31, event.startTick, event.slot), dropId: event.dropId }) }
    const check = applyDropEvents(frame.buffer.slice(frame.byteOffset, frame.byteOffset + frame.byteLength), 1000, { view, clock, add })
    expect(added).toEqual([fresh.dropId])
    expect(check).toMatchObject({ check: { ok: true, tick: 9, server: hash, balls: 2 }, events: 2 })
    expect(clock.stats.observations).toBe(1)
    const forged = encodeDropEvents(12, '0000000000000000', [])
    expect(applyDropEvents(forged, 1100, { view, clock, add }).check.ok).toBe(false)
    const snapshot = encodeSnapshot(5, new Uint8Array(1), 0, new Float64Array(0), new Float64Array(0), 16, 0, 1)
    expect(applyDropEvents(snapshot, 1200, { view, clock, add })).toBe(null)
    expect(pageDelivery('')).toBe('seeds')
    expect(pageDelivery('?delivery=snapshots')).toBe('snapshots')
    expect(pageDelivery('?delivery=other')).toBe('seeds')
  })
})

describe('pong as a room clock sample', () => {
  it("keeps a quiet room's clock on the room's tick from the heartbeats' pongs alone", () => {
    const clock = new RoomClock({ tickRate: 60 })
    const joined = { room: '12-medium', clock }
    // A room at 60 ticks a second, answering a ping every 1 s; 40 ms one way, some arrivals later.
    for (let i = 0; i < 12; i++) {
      const sentAt = 1000 * i
      expect(applyPong({ type: 'pong', serverTime: 0, room: '12-medium', tick: 500 + 60 * i }, sentAt + 40 + (i % 3) * 15, joined)).toBe(true)
    }
    expect(clock.stats.observations).toBe(12)
    // The model's tick at a later arrival time: the room's tick then, less one way (40 ms = 2.4 ticks).
    expect(clock.estimateAt(12_040) - (500 + 60 * 12)).toBeCloseTo(0, 0)
    // Another room's pong (before a join was answered), one without a tick, or a snapshots room's timeline: not taken.
    expect(applyPong({ type: 'pong', serverTime: 0, room: '14-high', tick: 5 }, 12_100, joined)).toBe(false)
    expect(applyPong({ type: 'pong', serverTime: 0 }, 12_100, joined)).toBe(false)
    expect(applyPong({ type: 'pong', serverTime: 0, room: '12-medium', tick: 5 }, 12_100, { room: null, clock })).toBe(false)
    expect(applyPong({ type: 'pong', serverTime: 0, room: '12-medium', tick: 1300 }, 12_100, { room: '12-medium', clock: new SnapshotTimeline({ tickRate: 60, snapshotEvery: 3 }) })).toBe(false)
    expect(clock.stats.observations).toBe(12)
  })
})

describe('DropVerifier in seeds mode', () => {
  it("verifies the player's own drop from the live simulation's landing, and keeps no other player's drop pending", () => {
    const verifier = new DropVerifier()
    const room = new SeededRoom({ room: '12-medium', board })
    const announced = { ...drop(20, 0), player: 'a'.repeat(16) }
    const mine = verifier.expect(announced, { rows: 12, risk: 'medium' }, 'a'.repeat(16))
    verifier.expect(drop(21, 0), { rows: 12, risk: 'medium' }, 'a'.repeat(16))
    expect([...verifier.pending.keys()]).toEqual([mine.dropId])
    room.add(mine)
    room.complete(mine.dropId)
    const outcome = simulateDrop(board, mine.dropSeed)
    expect(verifier.settle({ dropId: mine.dropId, ...outcome }).verified).toBe(true)
    const other = verifier.expect({ ...drop(22, 0), player: 'a'.repeat(16) }, { rows: 12, risk: 'medium' }, 'a'.repeat(16))
    // Settled before this page simulated it (it left the room): simulated then.
    const forged = verifier.settle({ dropId: other.dropId, ...simulateDrop(board, other.dropSeed), stateHash: '0'.repeat(16) })
    expect(forged.verified).toBe(false)
  })
})

describe('RoomClock', () => {
  it('follows the room tick (earliest arrivals plus half the round trip), draws one way and the commit margin behind it, and never goes backwards', () => {
    let state = 7
    const random = () => ((state = (Math.imul(state, 1664525) + 1013904223) >>> 0) / 2 ** 32)
    const clock = new RoomClock({ tickRate: 60, rttMs: () => 40 })
    // The room sends its tick every 250 ms; each arrives 20 ms (one way) + up to 80 ms of jitter later.
    const arrivals = []
    for (let sentAt = 0; sentAt < 30_000; sentAt += 250) arrivals.push({ tick: sentAt * 60 / 1000, at: sentAt + 20 + random() * 80 })
    arrivals.sort((p, q) => p.at - q.at)
    let last = -Infinity
    let next = 0
    let error = null
    for (let now = 0; now < 30_000; now += 1000 / 60) {
      while (next < arrivals.length && arrivals[next].at <= now) clock.observe(arrivals[next].tick, arrivals[next++].at)
      const tick = clock.advance(now)
      if (tick === null) continue
      expect(tick).toBeGreaterThanOrEqual(last)
      last = tick
      error = tick - (now - 20 - SETTLE_MARGIN_MS) * 60 / 1000
    }
    // One way and the margin behind the room's tick now, within a couple of ticks (the jitter's earliest arrivals).
    expect(Math.abs(error)).toBeLessThan(2)
    expect(Math.abs(clock.estimateAt(30_000) - 30_000 * 60 / 1000)).toBeLessThan(2)
    expect(clock.stats.snaps).toBe(0)
  })
})
