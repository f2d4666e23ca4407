import { describe, it, expect } from 'vitest'
import { encodeSnapshot, decodeSnapshot, encodeRoomFrame, splitRoomFrame, quantizePosition } from '../../protocol/snapshot-codec.js'

/**
 * The binary frames of protocol/snapshot-codec.js, the one module the
 * server encodes with and the browser decodes with (served at /protocol/).
 */
function frame (balls, tick = 123456) {
  const span = Math.max(0, ...balls.map((b) => b.slot + 1))
  const visible = new Uint8Array(span + 5)
  const xs = new Float64Array(span + 5)
  const ys = new Float64Array(span + 5)
  for (const { slot, x, y } of balls) { visible[slot] = 1; xs[slot] = x; ys[slot] = y }
  return encodeSnapshot(tick, visible, span + 5, xs, ys)
}

/** WebSocket framing a server adds to a binary message of `length` bytes. */
const wsHeader = (length) => (length < 126 ? 2 : length < 65536 ? 4 : 10)

describe('snapshot frames', () => {
  it('round-trip slots and positions quantized to 0.5 px', () => {
    let state = 7
    const random = () => (state = (state * 16807) % 2147483647) / 2147483647
    const balls = []
    for (let slot = 0; slot < 300; slot++) {
      if (random() < 0.4) balls.push({ slot, x: random() * 1023.5, y: random() * 1023.5 })
    }
    const decoded = decodeSnapshot(frame(balls, 4_000_000_000))
    expect(decoded.tick).toBe(4_000_000_000)
    expect([...decoded.slots]).toEqual(balls.map((b) => b.slot))
    balls.forEach((ball, i) => {
      expect(decoded.xs[i]).toBe(Math.round(ball.x * 2) / 2)
      expect(decoded.ys[i]).toBe(Math.round(ball.y * 2) / 2)
      expect(Math.abs(decoded.xs[i] - ball.x)).toBeLessThanOrEqual(0.25)
    })
    // An ArrayBuffer (what a browser's socket delivers) reads the same.
    const bytes = frame(balls, 9)
    expect(decodeSnapshot(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength))).toEqual(decodeSnapshot(bytes))
  })

  it('clamp positions outside 0..1023.5 px', () => {
    expect(quantizePosition(-3)).toBe(0)
    expect(quantizePosition(5000)).toBe(2047)
    const decoded = decodeSnapshot(frame([{ slot: 3, x: -10, y: 2000 }]))
    expect([decoded.slots[0], decoded.xs[0], decoded.ys[0]]).toEqual([3, 0, 1023.5])
  })

  it('have the documented byte layout', () => {
    const bytes = frame([{ slot: 0, x: 1, y: 0.5 }, { slot: 9, x: 1023.5, y: 0 }], 0x01020304)
    expect([...bytes.subarray(0, 7)]).toEqual([1, 0x04, 0x03, 0x02, 0x01, 10, 0])
    expect([...bytes.subarray(7, 9)]).toEqual([0b00000001, 0b00000010]) // slots 0 and 9
    // 4 values × 11 bits = 44 bits → 6 bytes: 2, 1, 2047, 0 LSB-first.
    expect(bytes.length).toBe(7 + 2 + 6)
    const bits = [...bytes.subarray(9)].reduce((acc, byte, i) => acc + BigInt(byte) * (1n << BigInt(8 * i)), 0n)
    const mask = (1n << 11n) - 1n
    expect([0n, 11n, 22n, 33n].map((shift) => Number((bits >> shift) & mask))).toEqual([2, 1, 2047, 0])
    expect([...frame([])]).toEqual([1, 64, 226, 1, 0, 0, 0])
  })

  it('refuse truncated frames and other kinds', () => {
    const bytes = frame([{ slot: 3, x: 10, y: 20 }, { slot: 9, x: 30, y: 40 }], 9)
    expect(decodeSnapshot(bytes.slice(0, bytes.length - 1))).toBeNull()
    const other = bytes.slice()
    other[0] = 2
    expect(decodeSnapshot(other)).toBeNull()
    expect(decodeSnapshot(new ArrayBuffer(3))).toBeNull()
  })

  it('keep a 50-ball room under 4 KB/s per client at 20 Hz', () => {
    const balls = Array.from({ length: 50 }, (_, slot) => ({ slot, x: 100 + slot, y: 200 + slot }))
    const bytes = frame(balls).length
    expect(bytes).toBe(7 + 7 + Math.ceil(50 * 22 / 8))
    expect((bytes + wsHeader(bytes)) * 20).toBeLessThan(4000)
  })
})

describe('room frames', () => {
  it('split into their events (UTF-8 JSON) and their snapshot', () => {
    const snapshot = frame([{ slot: 0, x: 10, y: 20 }, { slot: 3, x: 300.5, y: 512 }], 42)
    const events = [{ type: 'dropped', dropId: 7, player: 'p-ü', clientSeed: 'naïve ✓' }, { type: 'settled', dropId: 5, payout: 12 }]
    const encoded = encodeRoomFrame(JSON.stringify(events), snapshot)
    expect(encoded[0]).toBe(2)
    const split = splitRoomFrame(encoded)
    expect(split.events).toEqual(events)
    expect(decodeSnapshot(split.snapshot)).toEqual(decodeSnapshot(snapshot))
    expect(splitRoomFrame(encoded.buffer.slice(0)).events).toEqual(events)
    // A plain snapshot frame passes through with no events.
    expect(splitRoomFrame(snapshot)).toEqual({ events: [], snapshot })
  })

  it('refuse truncated or foreign frames', () => {
    const encoded = encodeRoomFrame('[{"type":"dropped"}]', frame([], 1))
    expect(splitRoomFrame(encoded.slice(0, 10))).toBeNull()
    expect(splitRoomFrame(new Uint8Array([9, 0, 0]))).toBeNull()
    expect(splitRoomFrame(new ArrayBuffer(0))).toBeNull()
    const notJson = new Uint8Array([2, 3, 0, 0, 0, ...new TextEncoder().encode('{x]'), ...frame([], 1)])
    expect(splitRoomFrame(notJson)).toBeNull()
    expect(splitRoomFrame(new Uint8Array([2, 3, 0, 0, 0, ...new TextEncoder().encode('{}1')]))).toBeNull() // not an array
  })
})
