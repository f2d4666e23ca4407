import { describe, it, expect } from 'vitest'
import { createBoard } from '../../engine/index.js'
import { Room } from '../../server/rooms/room.js'
import { createDrop } from '../../server/game/drop.js'
import { seedsDelivery, RELEASED_FRAMES_PER_TICK } from '../../server/realtime/delivery-seeds.js'
import { DropLifecycle } from '../../server/game/drop-lifecycle.js'
import { betCost } from '../../server/game/money.js'
import { createMetrics } from '../../server/metrics.js'
import { decodeDropEvents } from '../../protocol/drop-events-codec.js'

/**
 * The seeds feed's frame waits for a commit in progress: a frame due while
 * a drop released before it is still being committed goes out as soon as
 * that drop's batch is committed (between two ticks, at most half a period
 * late), and the period's grid stays where it was. A real Room and SeedFeed; the sockets are
 * stand-ins that keep the frames they are sent, and the group commit is
 * played by hand (announce = what DropLifecycle does once it is durable).
 */

const EVENT_EVERY = 15
const MAX_HOLD = EVENT_EVERY >> 1

function setUp () {
  const room = new Room({ id: '10-low', board: createBoard({ rows: 10, risk: 'low' }), snapshotEvery: 3, eventEvery: EVENT_EVERY, checkEvery: 120 })
  const watcher = standInSocket('aaaaaaaaaaaaaaaa')
  const dropper = standInSocket('bbbbbbbbbbbbbbbb')
  room.join(watcher, seedsDelivery)
  room.join(dropper, seedsDelivery)
  const tally = { eventFrames: 0, eventBytes: 0, snapshotFrames: 0, snapshotBytes: 0 }
  let nextId = 1
  /** Ticks in which other rooms have written RELEASED_FRAMES_PER_TICK frames before this one's turn. */
  const busyTicks = new Set()
  return {
    room,
    watcher,
    dropper,
    tally,
    busyTicks,
    /** Accepts a drop of the dropper's at the room's current tick (its commit pending). */
    release () {
      const id = nextId++
      const drop = createDrop({
        id,
        account: dropper.account,
        room,
        nonce: id,
        dropSeed: id.toString(16).padStart(64, '0'),
        bet: 10,
        clientSeedChange: null,
        ref: undefined,
        origin: dropper
      })
      room.release(drop)
      return drop
    },
    /** Its commit is done: what DropLifecycle._committed does for a drop. */
    announce (drop) {
      drop.announced = true
      room.show(drop)
      room.dropAnnounced(drop, '{}')
    },
    /** Steps the room to `tick`, each tick delivered as the arena does. */
    stepTo (tick) {
      while (room.tick < tick) {
        room.step(() => {})
        // As the arena's tally: this tick's frames so far, the other rooms' first.
        tally.eventFrames = busyTicks.has(room.tick) ? RELEASED_FRAMES_PER_TICK : 0
        room.deliver(tally)
      }
    }
  }
}

function standInSocket (playerId) {
  return {
    account: { playerId, seed: { id: `seed-${playerId}`, hash: 'h' }, clientSeed: 'c', connections: new Set(), reserved: 0, commits: 0, balance: 0 },
    frames: [],
    takeDeferred: () => null,
    sendEventFrame (message) {
      this.frames.push(decodeDropEvents(message.payload))
      return true
    }
  }
}

const ids = (frame) => frame.events.map((e) => e.dropId)

describe('seeds feed: a due frame waits for a commit in progress', () => {
  it('sends the frame on the tick after the commit, not a period later, and keeps the grid', () => {
    const { watcher, release, announce, stepTo } = setUp()
    stepTo(10)
    const drop = release() // start tick 10, committed only after the frame of tick 15 was due
    stepTo(15)
    expect(watcher.frames).toEqual([])
    stepTo(17)
    expect(watcher.frames).toEqual([])
    announce(drop)
    stepTo(18)
    expect(watcher.frames.map((f) => f.tick)).toEqual([18])
    expect(ids(watcher.frames[0])).toEqual([drop.id])

    // The next frame is due on the grid again (tick 30), not a period after 18.
    const later = release()
    announce(later)
    stepTo(29)
    expect(watcher.frames).toHaveLength(1)
    stepTo(30)
    expect(watcher.frames.map((f) => f.tick)).toEqual([18, 30])
    expect(ids(watcher.frames[1])).toEqual([later.id])
  })

  it('sends a held frame as soon as its batch is committed, between two ticks, with the tick it was due on', () => {
    const { room, watcher, tally, release, announce, stepTo } = setUp()
    stepTo(10)
    const drop = release()
    stepTo(15)
    expect(watcher.frames).toEqual([])
    announce(drop)
    room.batchCommitted(tally) // what the arena does once the batch is applied
    expect(watcher.frames.map((f) => f.tick)).toEqual([15])
    expect(ids(watcher.frames[0])).toEqual([drop.id])
    expect(tally.eventFrames).toBe(1)
    // Nothing more at the next tick; the next frame on the grid.
    stepTo(29)
    expect(watcher.frames).toHaveLength(1)
    const later = release()
    announce(later)
    room.batchCommitted(tally) // nothing held: nothing sent off the grid
    expect(watcher.frames).toHaveLength(1)
    stepTo(30)
    expect(watcher.frames.map((f) => f.tick)).toEqual([15, 30])
  })

  it('keeps a frame held when a committed batch leaves a drop released before its tick still being committed', () => {
    const { room, watcher, tally, release, announce, stepTo } = setUp()
    stepTo(11)
    const first = release()
    stepTo(12)
    const second = release()
    stepTo(15)
    announce(first)
    room.batchCommitted(tally)
    expect(watcher.frames).toEqual([])
    announce(second)
    room.batchCommitted(tally)
    expect(watcher.frames.map((f) => f.tick)).toEqual([15])
    expect(ids(watcher.frames[0])).toEqual([first.id, second.id])
  })

  it('leaves a frame whose batch is committed to the next tick while RELEASED_FRAMES_PER_TICK frames went since the last began', () => {
    const { room, watcher, tally, release, announce, stepTo } = setUp()
    stepTo(10)
    const drop = release()
    stepTo(15)
    announce(drop)
    tally.eventFrames = RELEASED_FRAMES_PER_TICK // other rooms released theirs first
    room.batchCommitted(tally)
    expect(watcher.frames).toEqual([])
    stepTo(16)
    expect(watcher.frames.map((f) => f.tick)).toEqual([16])
  })

  it('sends a due frame at once when every drop released before it is announced', () => {
    const { watcher, release, announce, stepTo } = setUp()
    stepTo(5)
    const drop = release()
    announce(drop)
    stepTo(15)
    expect(watcher.frames.map((f) => f.tick)).toEqual([15])
  })

  it('waits only for drops released before the due tick', () => {
    const { watcher, release, announce, stepTo } = setUp()
    stepTo(12)
    const before = release()
    stepTo(15)
    const after = release() // start tick 15: accepted once the frame was due
    stepTo(16)
    announce(before)
    stepTo(17)
    // Sent although `after` is still being committed; it goes in the next frame.
    expect(watcher.frames.map((f) => f.tick)).toEqual([17])
    expect(ids(watcher.frames[0])).toEqual([before.id])
    announce(after)
    stepTo(30)
    expect(watcher.frames.map((f) => f.tick)).toEqual([17, 30])
    expect(ids(watcher.frames[1])).toEqual([after.id])
  })

  it('lets a frame whose commit is done wait while its tick has written its share of frames, at most half a period', () => {
    const { watcher, busyTicks, release, announce, stepTo } = setUp()
    stepTo(10)
    const drop = release()
    stepTo(16)
    announce(drop)
    // Other rooms released a slow commit's frames in ticks 17 and 18: this one goes in 19.
    busyTicks.add(17).add(18)
    stepTo(18)
    expect(watcher.frames).toEqual([])
    stepTo(19)
    expect(watcher.frames.map((f) => f.tick)).toEqual([19])
    expect(ids(watcher.frames[0])).toEqual([drop.id])

    // Busy all along: it goes once held half a period, as a slow commit's frame does.
    const next = release()
    stepTo(30)
    announce(next)
    for (let tick = 31; tick <= 45; tick++) busyTicks.add(tick)
    stepTo(30 + MAX_HOLD - 1)
    expect(watcher.frames).toHaveLength(1)
    stepTo(30 + MAX_HOLD)
    expect(watcher.frames.map((f) => f.tick)).toEqual([19, 30 + MAX_HOLD])
    // A frame due on the grid is not held for the count: the next one goes on tick 45, busy or not.
    announce(release())
    stepTo(45)
    expect(watcher.frames.map((f) => f.tick)).toEqual([19, 30 + MAX_HOLD, 45])
  })

  it('holds a frame at most half a period: a slower commit comes in the next frame', () => {
    const { watcher, release, announce, stepTo } = setUp()
    stepTo(12)
    const announced = release()
    announce(announced)
    const slow = release()
    stepTo(15 + MAX_HOLD - 1)
    expect(watcher.frames).toEqual([])
    stepTo(15 + MAX_HOLD)
    expect(watcher.frames.map((f) => f.tick)).toEqual([15 + MAX_HOLD])
    expect(ids(watcher.frames[0])).toEqual([announced.id])
    announce(slow)
    stepTo(30)
    expect(watcher.frames.map((f) => f.tick)).toEqual([15 + MAX_HOLD, 30])
    expect(ids(watcher.frames[1])).toEqual([slow.id])
  })

  it('stops waiting once a drop it carries has waited more than a period: the slower one comes in the next frame', () => {
    const { watcher, release, announce, stepTo } = setUp()
    stepTo(3)
    const early = release() // accepted just after the frame of tick 0: at tick 15 it has waited 12 ticks
    announce(early)
    stepTo(14)
    const slow = release()
    stepTo(18)
    expect(watcher.frames).toEqual([]) // held for `slow` while `early` has waited at most a period (15 ticks)
    stepTo(19)
    expect(watcher.frames.map((f) => f.tick)).toEqual([19])
    expect(ids(watcher.frames[0])).toEqual([early.id])
    announce(slow)
    stepTo(30)
    expect(watcher.frames.map((f) => f.tick)).toEqual([19, 30])
    expect(ids(watcher.frames[1])).toEqual([slow.id])
  })

  it('does not hold a due frame at all for a drop that has waited more than a period already', () => {
    const { watcher, release, announce, stepTo } = setUp()
    stepTo(14)
    const missed = release() // its commit outlasted the frame of tick 15's hold: it waits for tick 30
    stepTo(15)
    const slow = release()
    stepTo(29)
    announce(missed)
    expect(watcher.frames).toEqual([])
    stepTo(30)
    // `missed` (16 ticks old) goes now although `slow`, released before tick 30 too, is still being committed.
    expect(watcher.frames.map((f) => f.tick)).toEqual([30])
    expect(ids(watcher.frames[0])).toEqual([missed.id])
    announce(slow)
    stepTo(45)
    expect(ids(watcher.frames[1])).toEqual([slow.id])
  })

  it('stops waiting for a drop whose commit failed', () => {
    const { room, watcher, release, announce, stepTo } = setUp()
    stepTo(4)
    const kept = release()
    announce(kept)
    const failed = release()
    stepTo(16)
    expect(watcher.frames).toEqual([])
    room.discard(failed)
    stepTo(17)
    expect(watcher.frames.map((f) => f.tick)).toEqual([17])
    expect(ids(watcher.frames[0])).toEqual([kept.id])
  })

  it('waits for no drop once every one released is announced, however many are in flight, and for one that is not', () => {
    const { room, release, announce, stepTo } = setUp()
    for (let i = 0; i < 500; i++) {
      announce(release())
      stepTo(room.tick + 1)
    }
    expect(room.ballsInFlight).toBeGreaterThan(100)
    expect(room.awaitsCommitBefore(room.tick + 1)).toBe(false)
    release()
    expect(room.awaitsCommitBefore(room.tick)).toBe(false) // released at this tick, not before it
    expect(room.awaitsCommitBefore(room.tick + 1)).toBe(true)
  })
})

describe('DropLifecycle: the rooms of a batch hear of it once it is applied or refused', () => {
  /** A store whose commits the test settles one at a time. */
  function manualStore () {
    const pending = []
    return { pending, commitBatch: (batch) => new Promise((resolve, reject) => pending.push({ batch, resolve, reject })) }
  }

  function lifecycleFor (room, store) {
    const told = []
    const tally = { eventFrames: 0, eventBytes: 0, snapshotFrames: 0, snapshotBytes: 0 }
    const lifecycle = new DropLifecycle({
      config: { spectatorEvents: 'snapshot' },
      store,
      accounts: { release () {} },
      sequences: {},
      feed: { balancesCommitted () {} },
      metrics: createMetrics({ defaultMetrics: false }),
      log: { error () {}, warn () {} },
      // As the arena wires it (Arena._roomsCommitted), noting what it was told.
      onRoomsCommitted: (rooms) => {
        told.push([...rooms].map((r) => r.id))
        for (const r of rooms) r.batchCommitted(tally)
      }
    })
    return { lifecycle, told }
  }

  const settle = () => new Promise((resolve) => setImmediate(resolve))

  it('sends the frame held for a drop when its batch commits, and its room is told once', async () => {
    const { room, watcher, dropper, release, stepTo } = setUp()
    const store = manualStore()
    const { lifecycle, told } = lifecycleFor(room, store)
    stepTo(10)
    const drop = release()
    dropper.account.reserved += betCost(drop.bet)
    lifecycle.ledger.addDrop(drop)
    stepTo(15)
    lifecycle.ledger.flush()
    await settle()
    expect(watcher.frames).toEqual([])
    store.pending[0].resolve({ rejected: new Map(), settled: new Set(), balances: new Map([[dropper.account.playerId, 1_000_000 - betCost(drop.bet)]]) })
    await settle()
    expect(told).toEqual([[room.id]])
    expect(drop.announced).toBe(true)
    expect(watcher.frames.map((f) => f.tick)).toEqual([15])
    expect(ids(watcher.frames[0])).toEqual([drop.id])
  })

  it('sends the frame without a drop whose batch failed', async () => {
    const { room, watcher, dropper, release, announce, stepTo } = setUp()
    const store = manualStore()
    const { lifecycle, told } = lifecycleFor(room, store)
    stepTo(8)
    const kept = release()
    announce(kept)
    stepTo(10)
    const failed = release()
    dropper.account.reserved += betCost(failed.bet)
    lifecycle.ledger.addDrop(failed)
    stepTo(15)
    lifecycle.ledger.flush()
    await settle()
    expect(watcher.frames).toEqual([])
    store.pending[0].reject(new Error('disk full'))
    await settle()
    expect(told).toEqual([[room.id]])
    expect(failed.void).toBe(true)
    expect(watcher.frames.map((f) => f.tick)).toEqual([15])
    expect(ids(watcher.frames[0])).toEqual([kept.id])
  })
})
