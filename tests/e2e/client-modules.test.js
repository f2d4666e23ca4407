/**
 * The browser client's pure modules, run in Node: the snapshot decoder
 * against the server's encoder, and the playout clock of
 * SnapshotTimeline (out-of-order frames slotted in, stale ones dropped,
 * the render clock never going backwards), and the socket URL the page
 * connects to, before and after an E_WRONG_NODE redirect.
 */
import { describe, it, expect } from 'vitest'
import { encodeSnapshot, encodeRoomFrame, splitRoomFrame as serverSplit, decodeSnapshot as serverDecode } from '../../server/rooms/snapshot-codec.js'
import { decodeSnapshot, splitRoomFrame, socketUrl, parseRoomId as clientParseRoomId } from '../../client/protocol.js'
import { ROOM_IDS, parseRoomId as serverParseRoomId } from '../../server/rooms/room-id.js'
import { SnapshotTimeline } from '../../client/snapshot-timeline.js'

function lcg (seed) {
  let state = seed >>> 0
  return () => {
    state = (Math.imul(state, 1664525) + 1013904223) >>> 0
    return state / 2 ** 32
  }
}

function frame (tick, balls) {
  const visible = new Uint8Array(256)
  const xs = new Float64Array(256)
  const ys = new Float64Array(256)
  for (const { slot, x, y } of balls) { visible[slot] = 1; xs[slot] = x; ys[slot] = y }
  const buffer = encodeSnapshot(tick, visible, 256, xs, ys)
  return buffer.buffer.slice(buffer.byteOffset, buffer.byteOffset + buffer.byteLength)
}

describe('client snapshot decoder', () => {
  it('reads what the server encodes, exactly as the server\'s reference decoder does', () => {
    const random = lcg(7)
    for (let round = 0; round < 200; round++) {
      const balls = []
      for (let slot = 0; slot < 200; slot++) if (random() < 0.2) balls.push({ slot, x: random() * 1100 - 20, y: random() * 1100 - 20 })
      const bytes = frame(round * 3, balls)
      const mine = decodeSnapshot(bytes)
      const reference = serverDecode(new Uint8Array(bytes))
      expect(mine.tick).toBe(reference.tick)
      expect([...mine.slots]).toEqual(reference.balls.map((b) => b.slot))
      expect([...mine.xs]).toEqual(reference.balls.map((b) => b.x))
      expect([...mine.ys]).toEqual(reference.balls.map((b) => b.y))
    }
  })

  it('refuses truncated frames and other kinds', () => {
    const bytes = new Uint8Array(frame(9, [{ slot: 3, x: 10, y: 20 }, { slot: 9, x: 30, y: 40 }]))
    expect(decodeSnapshot(bytes.slice(0, bytes.length - 1).buffer)).toBeNull()
    const other = bytes.slice()
    other[0] = 2
    expect(decodeSnapshot(other.buffer)).toBeNull()
    expect(decodeSnapshot(new ArrayBuffer(3))).toBeNull()
  })
})

describe('SnapshotTimeline', () => {
  const snapshot = (tick) => ({ tick, slots: new Int32Array(0), xs: new Float32Array(0), ys: new Float32Array(0) })

  it('slots late frames in by tick, drops duplicates and frames older than the render point', () => {
    const timeline = new SnapshotTimeline({ tickRate: 60, snapshotEvery: 3 })
    expect(timeline.push(snapshot(3), 50)).toBe('accepted')
    expect(timeline.push(snapshot(9), 150)).toBe('accepted')
    expect(timeline.push(snapshot(6), 160)).toBe('accepted') // late, out of order
    expect(timeline.push(snapshot(6), 170)).toBe('duplicate')
    expect(timeline.buffer.map((s) => s.tick)).toEqual([3, 6, 9])
    expect(timeline.stats.outOfOrder).toBe(1)
    const { a, b } = timeline.bracket(7)
    expect([a.tick, b.tick]).toEqual([6, 9])
    expect(timeline.buffer.map((s) => s.tick)).toEqual([6, 9])
    expect(timeline.push(snapshot(4), 200)).toBe('stale')
    expect(timeline.stats.stale).toBe(1)
  })

  it('renders ~100 ms behind a steady server, further behind a jittery one, and never goes backwards', () => {
    for (const maxDelayMs of [0, 150]) {
      const random = lcg(42)
      const timeline = new SnapshotTimeline({ tickRate: 60, snapshotEvery: 3 })
      const arrivals = []
      for (let tick = 3; tick <= 1800; tick += 3) arrivals.push({ tick, at: tick * 1000 / 60 + 20 + random() * maxDelayMs })
      arrivals.sort((p, q) => p.at - q.at)
      let last = -Infinity
      let next = 0
      let lag = 0
      for (let now = 0; now < 30_500; now += 1000 / 60) {
        while (next < arrivals.length && arrivals[next].at <= now) timeline.push(snapshot(arrivals[next++].tick), arrivals[next - 1].at)
        const tick = timeline.advance(now)
        if (tick === null) continue
        expect(tick).toBeGreaterThanOrEqual(last)
        last = tick
        timeline.bracket(tick)
        lag = now * 60 / 1000 - tick
      }
      expect(timeline.stats.snaps).toBe(0)
      if (maxDelayMs === 0) {
        expect(timeline.delayMs).toBe(100)
        expect(lag * 1000 / 60).toBeGreaterThan(100)
        expect(lag * 1000 / 60).toBeLessThan(140)
      } else {
        expect(timeline.stats.outOfOrder).toBeGreaterThan(0)
        expect(timeline.delayMs).toBeGreaterThan(150)
      }
    }
  })

  it('learns the server\'s real tick rate', () => {
    const timeline = new SnapshotTimeline({ tickRate: 60, snapshotEvery: 3 })
    for (let tick = 3; tick <= 900; tick += 3) timeline.push(snapshot(tick), tick * 1000 / 180)
    expect(timeline.rate * 1000).toBeCloseTo(180, 3)
  })
})

describe('client socket URL', () => {
  it('connects beside the page, or to the process E_WRONG_NODE names, over ws or wss', () => {
    expect(socketUrl('http://localhost:8080/', 'abc')).toBe('ws://localhost:8080/ws?token=abc')
    expect(socketUrl('https://play.example/', 't')).toBe('wss://play.example/ws?token=t')
    // A page served under a process prefix, and an E_WRONG_NODE owner (no trailing slash).
    expect(socketUrl('http://lb:8080/n/server1/', 't')).toBe('ws://lb:8080/n/server1/ws?token=t')
    expect(socketUrl('http://lb:8080/n/server2', 't')).toBe('ws://lb:8080/n/server2/ws?token=t')
    expect(socketUrl('http://h/', 'a b&c')).toBe('ws://h/ws?token=a%20b%26c')
  })

  it('refuses anything but an absolute http(s) URL', () => {
    for (const bad of ['javascript:alert(1)', 'ftp://h/', '/n/1', '', 'not a url']) expect(socketUrl(bad, 't')).toBeNull()
  })
})

describe('client room frames', () => {
  const toArrayBuffer = (buffer) => buffer.buffer.slice(buffer.byteOffset, buffer.byteOffset + buffer.byteLength)

  it('splits what the server encodes into its events (UTF-8 JSON) and its snapshot', () => {
    const snapshot = Buffer.from(frame(42, [{ slot: 0, x: 10, y: 20 }, { slot: 3, x: 300.5, y: 512 }]))
    const events = [{ type: 'dropped', dropId: 7, player: 'p-ü', clientSeed: 'naïve ✓' }, { type: 'settled', dropId: 5, payout: 12 }]
    const encoded = encodeRoomFrame(JSON.stringify(events), snapshot)
    const split = splitRoomFrame(toArrayBuffer(encoded))
    expect(split.events).toEqual(events)
    expect(decodeSnapshot(split.snapshot)).toEqual(decodeSnapshot(toArrayBuffer(snapshot)))
    expect(serverSplit(encoded).events).toEqual(events)
    expect(serverDecode(serverSplit(encoded).snapshot).balls.map((b) => b.slot)).toEqual([0, 3])
    // A plain snapshot frame passes through with no events.
    expect(splitRoomFrame(toArrayBuffer(snapshot))).toEqual({ events: [], snapshot: toArrayBuffer(snapshot) })
  })

  it('refuses truncated or foreign frames', () => {
    const encoded = toArrayBuffer(encodeRoomFrame('[{"type":"dropped"}]', Buffer.from(frame(1, []))))
    expect(splitRoomFrame(encoded.slice(0, 10))).toBeNull()
    expect(splitRoomFrame(new Uint8Array([9, 0, 0]).buffer)).toBeNull()
    expect(splitRoomFrame(new ArrayBuffer(0))).toBeNull()
    const notJson = Buffer.concat([Buffer.from([2, 3, 0, 0, 0]), Buffer.from('{x]'), Buffer.from(frame(1, []))])
    expect(splitRoomFrame(toArrayBuffer(notJson))).toBeNull()
  })
})

describe('client room ids', () => {
  it('reads every room id the server knows as the server does, and no other', () => {
    for (const id of ROOM_IDS) expect(clientParseRoomId(id), id).toEqual(serverParseRoomId(id))
    for (const id of ['16-medium.1', '16-medium.9', '16-medium.02', '7-low', '17-high.2', '16-extreme', '']) {
      expect(clientParseRoomId(id), id).toBeNull()
      expect(serverParseRoomId(id), id).toBeNull()
    }
  })
})
