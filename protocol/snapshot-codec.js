/**
 * The binary frames of the game protocol, one module for the server (which
 * encodes them) and the browser (which decodes them): served to the page
 * at /protocol/ as it is in the repository, like the engine.
 *
 * Snapshot frame: every visible ball's position in one room at one tick,
 * encoded once per room and sent as the same bytes to all its clients.
 * Little-endian:
 *
 *   offset  size            field
 *   0       1               kind = 1 (SNAPSHOT_KIND)
 *   1       4               tick, uint32: the room tick the positions belong to
 *   5       2               slotSpan S, uint16: highest visible slot + 1 (0: no balls)
 *   7       ceil(S/8)       presence bitmask: slot s is present iff bit (s & 7) of byte (s >> 3) is set
 *   …       ceil(22·N/8)    N = number of present slots; for each, in ascending slot order,
 *                           x then y as 11-bit unsigned q = round(px · 2) clamped to 0..2047
 *                           (0.5 px steps, 0..1023.5 px), packed LSB-first into one bit
 *                           stream; the last byte is zero-padded
 *
 * A slot is the ball's small per-room number, announced with its drop id in
 * `dropped` (and `joined`). 50 balls in slots 0..49 take 7 + 7 + 138 = 152
 * bytes. Angles are not sent: a client that wants the exact pose replays the
 * drop from its seed.
 *
 * Room frame: the other players' `dropped`/`settled` events of the last
 * snapshot period and the snapshot, in one binary frame (a spectator gets one
 * frame per snapshot instead of one per event):
 *
 *   offset  size   field
 *   0       1      kind = 2 (ROOM_FRAME_KIND)
 *   1       4      L, uint32: byte length of the events
 *   5       L      the events: a JSON array of `dropped`/`settled` messages (UTF-8), oldest first
 *   5 + L   …      a snapshot frame (kind 1, above), whose balls those events named first
 */
export const SNAPSHOT_KIND = 1
export const ROOM_FRAME_KIND = 2
export const POSITION_BITS = 11
export const POSITION_STEPS_PER_PX = 2
export const MAX_POSITION = (1 << POSITION_BITS) - 1
const HEADER_BYTES = 7

// Created on first use: a page or tool that only decodes snapshots needs neither.
let encoder = null
let decoder = null

/** @param {number} px @returns {number} the 11-bit position */
export function quantizePosition (px) {
  const q = Math.round(px * POSITION_STEPS_PER_PX)
  return q < 0 ? 0 : (q > MAX_POSITION ? MAX_POSITION : q)
}

/**
 * @param {number} tick
 * @param {Uint8Array} visible 1 at every slot to include
 * @param {number} slotLimit only slots below this are considered
 * @param {Float64Array} xs x of slot s at xs[s × stride + xOffset]
 * @param {Float64Array} ys y of slot s at ys[s × stride + yOffset]
 * @param {number} [stride] 1 for arrays by slot; the world's BODY_STRIDE for its body state
 * @param {number} [xOffset] @param {number} [yOffset]
 * @returns {Uint8Array}
 */
export function encodeSnapshot (tick, visible, slotLimit, xs, ys, stride = 1, xOffset = 0, yOffset = 0) {
  let span = 0
  let count = 0
  for (let slot = 0; slot < slotLimit; slot++) {
    if (visible[slot] === 1) { span = slot + 1; count++ }
  }
  if (span > 0xffff) throw new RangeError('too many slots for a snapshot')
  const maskBytes = (span + 7) >> 3
  const bytes = new Uint8Array(HEADER_BYTES + maskBytes + ((count * 2 * POSITION_BITS + 7) >> 3))
  bytes[0] = SNAPSHOT_KIND
  const u32 = tick >>> 0
  bytes[1] = u32 & 0xff; bytes[2] = (u32 >>> 8) & 0xff; bytes[3] = (u32 >>> 16) & 0xff; bytes[4] = u32 >>> 24
  bytes[5] = span & 0xff; bytes[6] = span >>> 8
  let offset = HEADER_BYTES + maskBytes
  let bits = 0
  let bitCount = 0
  for (let slot = 0; slot < span; slot++) {
    if (visible[slot] !== 1) continue
    bytes[HEADER_BYTES + (slot >> 3)] |= 1 << (slot & 7)
    bits |= quantizePosition(xs[slot * stride + xOffset]) << bitCount
    bitCount += POSITION_BITS
    bits |= quantizePosition(ys[slot * stride + yOffset]) << bitCount
    bitCount += POSITION_BITS
    while (bitCount >= 8) {
      bytes[offset++] = bits & 0xff
      bits >>>= 8
      bitCount -= 8
    }
  }
  if (bitCount > 0) bytes[offset++] = bits & 0xff
  return bytes
}

/**
 * @typedef {object} Snapshot
 * @property {number} tick the room tick the positions belong to
 * @property {Int32Array} slots present slots, ascending
 * @property {Float32Array} xs x per present slot (px, 0.5 px steps)
 * @property {Float32Array} ys y per present slot
 */

/**
 * Decodes a snapshot frame; null for a frame of another kind or a truncated one.
 * @param {Uint8Array | ArrayBuffer} frame
 * @returns {Snapshot | null}
 */
export function decodeSnapshot (frame) {
  const bytes = frame instanceof Uint8Array ? frame : new Uint8Array(frame)
  if (bytes.byteLength < HEADER_BYTES || bytes[0] !== SNAPSHOT_KIND) return null
  const tick = (bytes[1] | (bytes[2] << 8) | (bytes[3] << 16) | (bytes[4] << 24)) >>> 0
  const span = bytes[5] | (bytes[6] << 8)
  const maskBytes = (span + 7) >> 3
  if (bytes.byteLength < HEADER_BYTES + maskBytes) return null
  let count = 0
  for (let i = 0; i < maskBytes; i++) {
    for (let b = bytes[HEADER_BYTES + i]; b !== 0; b &= b - 1) count++
  }
  if (bytes.byteLength < HEADER_BYTES + maskBytes + ((count * 2 * POSITION_BITS + 7) >> 3)) return null
  const slots = new Int32Array(count)
  const xs = new Float32Array(count)
  const ys = new Float32Array(count)
  let offset = HEADER_BYTES + maskBytes
  let bits = 0
  let bitCount = 0
  const read = () => {
    while (bitCount < POSITION_BITS) {
      bits |= bytes[offset++] << bitCount
      bitCount += 8
    }
    const value = bits & MAX_POSITION
    bits >>>= POSITION_BITS
    bitCount -= POSITION_BITS
    return value / POSITION_STEPS_PER_PX
  }
  let n = 0
  for (let slot = 0; slot < span; slot++) {
    if ((bytes[HEADER_BYTES + (slot >> 3)] & (1 << (slot & 7))) === 0) continue
    slots[n] = slot
    xs[n] = read()
    ys[n] = read()
    n++
  }
  return { tick, slots, xs, ys }
}

/**
 * @param {string} eventsJson a JSON array
 * @param {Uint8Array} snapshot a kind-1 frame
 * @returns {Uint8Array}
 */
export function encodeRoomFrame (eventsJson, snapshot) {
  encoder ??= new TextEncoder()
  const events = encoder.encode(eventsJson)
  const bytes = new Uint8Array(5 + events.length + snapshot.length)
  const length = events.length
  bytes[0] = ROOM_FRAME_KIND
  bytes[1] = length & 0xff; bytes[2] = (length >>> 8) & 0xff; bytes[3] = (length >>> 16) & 0xff; bytes[4] = length >>> 24
  bytes.set(events, 5)
  bytes.set(snapshot, 5 + length)
  return bytes
}

/**
 * Splits a room frame (kind 2) into its events and snapshot frame. A
 * snapshot frame (kind 1) comes back whole with no events; anything else, or
 * a truncated frame, gives null.
 * @param {Uint8Array | ArrayBuffer} frame
 * @returns {{ events: object[], snapshot: Uint8Array } | null}
 */
export function splitRoomFrame (frame) {
  const bytes = frame instanceof Uint8Array ? frame : new Uint8Array(frame)
  if (bytes.byteLength < 1) return null
  if (bytes[0] === SNAPSHOT_KIND) return { events: [], snapshot: bytes }
  if (bytes[0] !== ROOM_FRAME_KIND || bytes.byteLength < 5) return null
  const length = (bytes[1] | (bytes[2] << 8) | (bytes[3] << 16) | (bytes[4] << 24)) >>> 0
  if (bytes.byteLength < 5 + length) return null
  let events
  try {
    decoder ??= new TextDecoder()
    events = JSON.parse(decoder.decode(bytes.subarray(5, 5 + length)))
  } catch {
    return null
  }
  return Array.isArray(events) ? { events, snapshot: bytes.subarray(5 + length) } : null
}
