import { describe, it, expect } from 'vitest'
import { createHmac } from 'node:crypto'
import { createBoard } from '../../engine/board.js'
import { DropSimulator, simulateDrop } from '../../engine/drop-simulator.js'
import { dropInitialConditions } from '../../engine/drop-initial-conditions.js'

const seed = (n) => createHmac('sha256', 'drop-simulator-test').update(String(n)).digest('hex')

describe('simulateDrop', () => {
  it('is a pure function of board and drop seed', () => {
    const board = createBoard({ rows: 14, risk: 'high' })
    for (let n = 0; n < 20; n++) {
      const a = simulateDrop(board, seed(n))
      const b = simulateDrop(createBoard({ rows: 14, risk: 'high' }), seed(n))
      expect(b).toEqual(a)
      expect(a.multiplier).toBe(board.multipliers[a.bucket])
      expect(a.stateHash).toMatch(/^[0-9a-f]{16}$/)
      expect(a.ticks).toBeGreaterThan(30)
    }
  })

  it('spreads drops over many buckets (physics, not a constant)', () => {
    const board = createBoard({ rows: 8, risk: 'low' })
    const buckets = new Set()
    for (let n = 0; n < 300; n++) buckets.add(simulateDrop(board, seed(n)).bucket)
    expect(buckets.size).toBeGreaterThanOrEqual(7)
  })

  it('returns the trajectory for replay: one pose per tick, from release to landing', () => {
    const board = createBoard({ rows: 10, risk: 'medium' })
    const plain = simulateDrop(board, seed(1))
    const replay = simulateDrop(board, seed(1), { trajectory: true })
    expect({ ...replay, trajectory: undefined }).toEqual({ ...plain, trajectory: undefined })
    expect(replay.trajectory.length).toBe((plain.ticks + 1) * 3)
    const start = dropInitialConditions(board, seed(1))
    expect(replay.trajectory[0]).toBe(start.x)
    expect(replay.trajectory[1]).toBe(start.y)
    expect(replay.trajectory[replay.trajectory.length - 2]).toBeGreaterThan(board.bucketLineY)
  })

  it('derives the release from the seed inside the drop zone', () => {
    const board = createBoard({ rows: 16, risk: 'low' })
    for (let n = 0; n < 100; n++) {
      const start = dropInitialConditions(board, seed(n))
      expect(start.x).toBeGreaterThanOrEqual(board.dropZone.minX)
      expect(start.x).toBeLessThanOrEqual(board.dropZone.maxX)
      expect(start.y).toBe(board.dropZone.y)
    }
    expect(dropInitialConditions(board, 'a')).not.toEqual(dropInitialConditions(board, 'b'))
    expect(() => dropInitialConditions(board, '')).toThrow(TypeError)
  })
})

describe('DropSimulator (a room)', () => {
  it('lands every ball exactly as it lands alone, whatever else is in flight', () => {
    const board = createBoard({ rows: 12, risk: 'medium' })
    const room = new DropSimulator(board)
    const released = new Map()
    const landed = new Map()
    let tick = 0
    // Release 60 balls at irregular ticks, several in the same tick.
    for (let n = 0; n < 60; n++) {
      while (tick < n * 7 - (n % 3) * 5) {
        for (const drop of room.step()) landed.set(drop.key, { ...drop, tick })
        tick++
      }
      room.addDrop(seed(n), n)
      released.set(n, tick)
    }
    while (room.inFlight > 0) {
      for (const drop of room.step()) landed.set(drop.key, { ...drop, tick })
      tick++
    }
    expect(landed.size).toBe(60)
    for (let n = 0; n < 60; n++) {
      const alone = simulateDrop(board, seed(n))
      const inRoom = landed.get(n)
      expect({ bucket: inRoom.bucket, ticks: inRoom.ticks, stateHash: inRoom.stateHash }).toEqual({ bucket: alone.bucket, ticks: alone.ticks, stateHash: alone.stateHash })
      // Released at tick T, it lands in the step that brings the room to T + ticks.
      expect(inRoom.tick + 1).toBe(released.get(n) + alone.ticks)
    }
  })
})

describe('the tick cap (board.maxDropTicks)', () => {
  it('lands a ball still in play after maxDropTicks where it is, in room and alone', () => {
    const board = createBoard({ rows: 16, risk: 'high' })
    const capped = { ...board, maxDropTicks: 12 }
    for (let n = 0; n < 10; n++) {
      const full = simulateDrop(board, seed(n), { trajectory: true })
      expect(full.ticks).toBeGreaterThan(12)
      const early = simulateDrop(capped, seed(n))
      expect(early.ticks).toBe(12)
      // Landed where the uncapped ball was after 12 ticks.
      const x = full.trajectory[12 * 3]
      expect(early.bucket).toBe(Math.max(0, Math.min(board.multipliers.length - 1, Math.floor((x - board.bucketLeftX) / board.bucketWidth))))
    }
    const room = new DropSimulator(capped)
    room.addDrop(seed(1), 'a')
    let landed = []
    for (let t = 0; t < 11; t++) expect(room.step()).toEqual([])
    landed = room.step()
    expect(landed.map((drop) => [drop.key, drop.ticks])).toEqual([['a', 12]])
    expect(room.inFlight).toBe(0)
  })

  it('ends the replay of a ball that can never cross the bucket line (a wedged ball cannot hang it)', () => {
    const board = createBoard({ rows: 8, risk: 'low' })
    const wedged = { ...board, bucketLineY: Infinity }
    const outcome = simulateDrop(wedged, seed(3))
    expect(outcome.ticks).toBe(board.maxDropTicks)
    expect(board.maxDropTicks).toBe(3600)
  })
})
