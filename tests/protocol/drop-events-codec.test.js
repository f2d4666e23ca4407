import { describe, it, expect } from 'vitest'
import fc from 'fast-check'
import { createBoard, DropSimulator, ENGINE_VERSIONS, StateHasher } from '../../engine/index.js'
import { encodeDropEvents, decodeDropEvents, scanDropEvents, withOwnMessages, FlightHasher, DROP_EVENTS_KIND, DROP_EVENT_BYTES, DROP_EVENTS_HEADER_BYTES } from '../../protocol/drop-events-codec.js'
import { encodeSnapshot } from '../../protocol/snapshot-codec.js'

/**
 * The seeds delivery's binary frame (protocol/drop-events-codec.js): the
 * server encodes it, the page and the lean player decode it, and both
 * compute the flight hash it carries.
 */
const hex = (length) => fc.stringMatching(new RegExp(`^[0-9a-f]{${length}}$`))
const dropArb = fc.record({
  id: fc.integer({ min: 0, max: Number.MAX_SAFE_INTEGER }),
  bet: fc.integer({ min: 0, max: Number.MAX_SAFE_INTEGER }),
  startTick: fc.integer({ min: 0, max: 0xffffffff }),
  slot: fc.integer({ min: 0, max: 0xffff }),
  engineVersion: fc.constantFrom(...ENGINE_VERSIONS),
  playerId: hex(16),
  dropSeed: hex(64)
})

describe('drop-events frames', () => {
  it('round-trip every field, whatever the values (property)', () => {
    fc.assert(fc.property(fc.integer({ min: 0, max: 0xffffffff }), hex(16), fc.array(dropArb, { maxLength: 40 }), (tick, hash, drops) => {
      const bytes = encodeDropEvents(tick, hash, drops)
      expect(bytes.length).toBe(DROP_EVENTS_HEADER_BYTES + DROP_EVENT_BYTES * drops.length)
      expect(bytes[0]).toBe(DROP_EVENTS_KIND)
      const decoded = decodeDropEvents(bytes)
      expect(decoded.tick).toBe(tick)
      expect(decoded.hash).toBe(hash)
      expect(decoded.events).toEqual(drops.map((d) => ({
        dropId: d.id, bet: d.bet, startTick: d.startTick, slot: d.slot, engineVersion: d.engineVersion, player: d.playerId, dropSeed: d.dropSeed
      })))
    }))
  })

  it('lay the fields out where the header comment says (a second reader gets the same bits)', () => {
    const drop = { id: 2 ** 40 + 5, bet: 250, startTick: 0x01020304, slot: 513, engineVersion: ENGINE_VERSIONS[1], playerId: '00112233445566ff', dropSeed: 'ab'.repeat(32) }
    const bytes = encodeDropEvents(70000, '89abcdef01234567', [drop])
    const view = new DataView(bytes.buffer)
    expect(view.getUint32(1, true)).toBe(70000)
    expect(view.getUint32(5, true)).toBe(0x89abcdef)
    expect(view.getUint32(9, true)).toBe(0x01234567)
    expect(view.getUint16(13, true)).toBe(1)
    const at = DROP_EVENTS_HEADER_BYTES
    expect(view.getUint32(at, true)).toBe(5)
    expect(view.getUint32(at + 4, true)).toBe(256)
    expect(view.getUint32(at + 8, true)).toBe(250)
    expect(view.getUint32(at + 16, true)).toBe(0x01020304)
    expect(view.getUint16(at + 20, true)).toBe(513)
    expect(bytes[at + 22]).toBe(1)
    expect(bytes[at + 23]).toBe(0)
    expect([...bytes.subarray(at + 24, at + 32)]).toEqual([0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0xff])
    expect([...bytes.subarray(at + 32, at + 64)]).toEqual(new Array(32).fill(0xab))
  })

  it('mark a player id that is not 16 hex digits instead of failing the whole frame', () => {
    const drop = { id: 1, bet: 1, startTick: 0, slot: 0, engineVersion: ENGINE_VERSIONS[0], playerId: 'p1', dropSeed: '0'.repeat(64) }
    const [event] = decodeDropEvents(encodeDropEvents(1, '0'.repeat(16), [drop])).events
    expect(event.player).toBe('')
    // 16 characters, hex but for the last two: flagged, and the tag all zero (not half written).
    const bytes = encodeDropEvents(1, '0'.repeat(16), [{ ...drop, playerId: 'ffffffffffffffzz' }])
    expect(bytes[DROP_EVENTS_HEADER_BYTES + 23]).toBe(1)
    expect([...bytes.subarray(DROP_EVENTS_HEADER_BYTES + 24, DROP_EVENTS_HEADER_BYTES + 32)]).toEqual(new Array(8).fill(0))
  })

  it('refuse to encode what the layout cannot carry', () => {
    const good = { id: 1, bet: 1, startTick: 0, slot: 0, engineVersion: ENGINE_VERSIONS[0], playerId: 'a'.repeat(16), dropSeed: 'f'.repeat(64) }
    expect(() => encodeDropEvents(1, 'xyz', [good])).toThrow(RangeError)
    expect(() => encodeDropEvents(1, '0'.repeat(16), [{ ...good, engineVersion: '9.9.9' }])).toThrow(/engine version/)
    expect(() => encodeDropEvents(1, '0'.repeat(16), [{ ...good, dropSeed: 'F'.repeat(64) }])).toThrow(/drop seed/)
    expect(() => encodeDropEvents(1, '0'.repeat(16), [{ ...good, id: -1 }])).toThrow(RangeError)
    expect(() => encodeDropEvents(1, '0'.repeat(16), [{ ...good, slot: 70000 }])).toThrow(/slot/)
  })

  it('decode to null when truncated, of another kind, or naming an unknown engine version (property)', () => {
    const drops = [{ id: 7, bet: 3, startTick: 9, slot: 2, engineVersion: ENGINE_VERSIONS[0], playerId: 'c'.repeat(16), dropSeed: 'd'.repeat(64) }]
    const bytes = encodeDropEvents(5, '1'.repeat(16), drops)
    fc.assert(fc.property(fc.integer({ min: 0, max: bytes.length - 1 }), (length) => {
      expect(decodeDropEvents(bytes.subarray(0, length))).toBeNull()
    }))
    const unknownVersion = bytes.slice()
    unknownVersion[DROP_EVENTS_HEADER_BYTES + 22] = 200
    expect(decodeDropEvents(unknownVersion)).toBeNull()
    expect(decodeDropEvents(encodeSnapshot(1, new Uint8Array(1), 1, new Float64Array(1), new Float64Array(1)))).toBeNull()
    // Any bytes at all: null or a frame, never an exception.
    fc.assert(fc.property(fc.uint8Array({ maxLength: 200 }), (junk) => {
      const decoded = decodeDropEvents(junk)
      expect(decoded === null || Array.isArray(decoded.events)).toBe(true)
    }))
    // An ArrayBuffer (what a browser's socket delivers) reads the same.
    expect(decodeDropEvents(bytes.buffer.slice(0))).toEqual(decodeDropEvents(bytes))
  })
})

describe('scanDropEvents (who dropped what, for readers of every frame)', () => {
  /** What scanDropEvents reports of a frame: its calls in order, then what it returns. */
  const scan = (bytes) => {
    const calls = []
    const result = scanDropEvents(bytes, (dropId, player, startTick, tick) => calls.push({ dropId, player, startTick, tick }))
    return { calls, result }
  }

  it("reports each event's drop id, player and start tick, the frame's tick and the owner's section as decodeDropEvents decodes them (property)", () => {
    const ownArb = fc.array(fc.record({ type: fc.constant('settled'), dropId: fc.nat(), note: fc.string() }), { maxLength: 3 })
    fc.assert(fc.property(fc.integer({ min: 0, max: 0xffffffff }), fc.array(dropArb, { maxLength: 30 }), ownArb, fc.boolean(), (tick, drops, own, notHex) => {
      if (notHex && drops.length > 0) drops[0] = { ...drops[0], playerId: 'not-a-hex-id' }
      const room = encodeDropEvents(tick, '0123456789abcdef', drops)
      const bytes = own.length > 0 ? withOwnMessages(room, own.map((m) => JSON.stringify(m))) : room
      const decoded = decodeDropEvents(bytes)
      const { calls, result } = scan(bytes)
      expect(calls).toEqual(decoded.events.map((e) => ({ dropId: e.dropId, player: e.player, startTick: e.startTick, tick: decoded.tick })))
      expect(result).toEqual({ tick: decoded.tick, own: decoded.own })
    }))
  })

  it('refuses what decodeDropEvents refuses, before reporting any event (property)', () => {
    const drops = [1, 2, 3].map((id) => ({ id, bet: 3, startTick: 9, slot: id, engineVersion: ENGINE_VERSIONS[0], playerId: 'c'.repeat(16), dropSeed: 'd'.repeat(64) }))
    const bytes = withOwnMessages(encodeDropEvents(5, '1'.repeat(16), drops), ['{"type":"settled"}'])
    fc.assert(fc.property(fc.integer({ min: 0, max: bytes.length - 1 }), (length) => {
      const truncated = bytes.subarray(0, length)
      const { calls, result } = scan(truncated)
      // A cut inside the owner's section leaves no JSON array; a cut right after the events is a frame without one.
      expect(result === null).toBe(decodeDropEvents(truncated) === null)
      if (result === null) expect(calls).toEqual([])
    }))
    const unknownVersion = bytes.slice()
    unknownVersion[DROP_EVENTS_HEADER_BYTES + 2 * DROP_EVENT_BYTES + 22] = 200 // the last event's
    expect(scan(unknownVersion)).toEqual({ calls: [], result: null })
    expect(scan(encodeSnapshot(1, new Uint8Array(1), 1, new Float64Array(1), new Float64Array(1)))).toEqual({ calls: [], result: null })
    fc.assert(fc.property(fc.uint8Array({ maxLength: 300 }), (junk) => {
      const { calls, result } = scan(junk)
      const decoded = decodeDropEvents(junk)
      expect(result === null).toBe(decoded === null)
      expect(calls).toEqual(decoded === null ? [] : decoded.events.map((e) => ({ dropId: e.dropId, player: e.player, startTick: e.startTick, tick: decoded.tick })))
    }))
  })
})

describe('the flight hash', () => {
  const board = createBoard({ rows: 12, risk: 'medium' })
  const seed = (n) => (n * 2654435761 >>> 0).toString(16).padStart(8, '0').repeat(8)

  it('is the StateHasher sequence the header specifies', () => {
    const expected = new StateHasher().reset().addInt32(42)
      .addInt32(3).addFloat64(1.5).addFloat64(2.25).addFloat64(-0.125).addFloat64(9)
      .addInt32(8).addFloat64(0.1).addFloat64(0.2).addFloat64(0.3).addFloat64(0.4)
      .digestHex()
    expect(new FlightHasher().begin(42).add(3, 1.5, 2.25, -0.125, 9).add(8, 0.1, 0.2, 0.3, 0.4).digest()).toBe(expected)
    expect(() => new FlightHasher().begin(1).add(4, 0, 0, 0, 0).add(4, 0, 0, 0, 0)).toThrow(/ascending/)
  })

  it("of a room's world equals the hash of each drop replayed alone and fast-forwarded to the room tick", () => {
    // The server hashes its room's one world; a page replays each drop by itself
    // from (seed, start tick). Both must give the same digest at every tick.
    const room = new DropSimulator(board)
    const starts = [[0, seed(1)], [5, seed(2)], [5, seed(3)], [40, seed(4)], [90, seed(5)]]
    const released = [] // { slot, seed, startTick }
    const hasher = new FlightHasher()
    const checked = []
    for (let tick = 0; tick <= 400; tick++) {
      for (const [startTick, dropSeed] of starts) {
        if (startTick === tick) released.push({ slot: room.addDrop(dropSeed), dropSeed, startTick })
      }
      room.step()
      const roomTick = tick + 1
      if (roomTick % 23 !== 0) continue
      const world = room.world
      hasher.begin(roomTick)
      let inFlight = 0
      for (let slot = 0; slot < world.bodyCount; slot++) {
        if (room.ticksOf(slot) < 0) continue
        hasher.add(slot, world.xOf(slot), world.yOf(slot), world.vxOf(slot), world.vyOf(slot))
        inFlight++
      }
      checked.push(inFlight)
      const serverHash = hasher.digest()

      const page = new FlightHasher().begin(roomTick)
      for (const ball of [...released].sort((a, b) => a.slot - b.slot)) {
        const alone = new DropSimulator(board)
        const id = alone.addDrop(ball.dropSeed)
        let landed = false
        for (let t = 0; t < roomTick - ball.startTick && !landed; t++) landed = alone.step().length > 0
        if (!landed) page.add(ball.slot, alone.world.xOf(id), alone.world.yOf(id), alone.world.vxOf(id), alone.world.vyOf(id))
      }
      expect(page.digest()).toBe(serverHash)
    }
    // The checks covered busy moments, a reused slot's and an empty board.
    expect(Math.max(...checked)).toBeGreaterThanOrEqual(3)
    expect(checked.at(-1)).toBe(0)
  })
})
