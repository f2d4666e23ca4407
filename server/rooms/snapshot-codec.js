/**
 * The binary snapshot frame: every visible ball's position in one room at
 * one tick, encoded once per room and sent as the same Buffer to all its
 * clients. Little-endian:
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
 */
export const SNAPSHOT_KIND = 1
/** A room frame: the room's events since the last frame, then its snapshot (see encodeRoomFrame). */
export const ROOM_FRAME_KIND = 2
export const POSITION_BITS = 11
export const POSITION_STEPS_PER_PX = 2
export const MAX_POSITION = (1 << POSITION_BITS) - 1
const HEADER_BYTES = 7

/** @param {number} px */
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
 * @returns {Buffer}
 */
export function encodeSnapshot (tick, visible, slotLimit, xs, ys, stride = 1, xOffset = 0, yOffset = 0) {
  let span = 0
  let count = 0
  for (let slot = 0; slot < slotLimit; slot++) {
    if (visible[slot] === 1) { span = slot + 1; count++ }
  }
  if (span > 0xffff) throw new RangeError('too many slots for a snapshot')
  const maskBytes = (span + 7) >> 3
  const buffer = Buffer.allocUnsafe(HEADER_BYTES + maskBytes + ((count * 2 * POSITION_BITS + 7) >> 3))
  buffer[0] = SNAPSHOT_KIND
  buffer.writeUInt32LE(tick >>> 0, 1)
  buffer.writeUInt16LE(span, 5)
  buffer.fill(0, HEADER_BYTES, HEADER_BYTES + maskBytes)
  let offset = HEADER_BYTES + maskBytes
  let bits = 0
  let bitCount = 0
  for (let slot = 0; slot < span; slot++) {
    if (visible[slot] !== 1) continue
    buffer[HEADER_BYTES + (slot >> 3)] |= 1 << (slot & 7)
    bits |= quantizePosition(xs[slot * stride + xOffset]) << bitCount
    bitCount += POSITION_BITS
    bits |= quantizePosition(ys[slot * stride + yOffset]) << bitCount
    bitCount += POSITION_BITS
    while (bitCount >= 8) {
      buffer[offset++] = bits & 0xff
      bits >>>= 8
      bitCount -= 8
    }
  }
  if (bitCount > 0) buffer[offset++] = bits & 0xff
  return buffer
}

/**
 * Decodes a snapshot frame (for tests, tools and as the reference for clients).
 * @param {Uint8Array} bytes
 * @returns {{ tick: number, balls: { slot: number, x: number, y: number }[] }}
 */
export function decodeSnapshot (bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
  if (view.getUint8(0) !== SNAPSHOT_KIND) throw new RangeError('not a snapshot frame')
  const tick = view.getUint32(1, true)
  const span = view.getUint16(5, true)
  const maskBytes = (span + 7) >> 3
  let offset = HEADER_BYTES + maskBytes
  let bits = 0
  let bitCount = 0
  const read = () => {
    while (bitCount < POSITION_BITS) {
      bits |= view.getUint8(offset++) << bitCount
      bitCount += 8
    }
    const value = bits & MAX_POSITION
    bits >>>= POSITION_BITS
    bitCount -= POSITION_BITS
    return value
  }
  const balls = []
  for (let slot = 0; slot < span; slot++) {
    if ((view.getUint8(HEADER_BYTES + (slot >> 3)) & (1 << (slot & 7))) === 0) continue
    const x = read() / POSITION_STEPS_PER_PX
    const y = read() / POSITION_STEPS_PER_PX
    balls.push({ slot, x, y })
  }
  return { tick, balls }
}

/**
 * The room frame: the other players' `dropped`/`settled` events of the last
 * snapshot period and the snapshot, in one binary frame, built once per room
 * and sent as the same Buffer to all its clients (a spectator gets one frame
 * per snapshot instead of one per event). Little-endian:
 *
 *   offset  size   field
 *   0       1      kind = 2 (ROOM_FRAME_KIND)
 *   1       4      L, uint32: byte length of the events
 *   5       L      the events: a JSON array of `dropped`/`settled` messages (UTF-8), oldest first
 *   5 + L   …      a snapshot frame (kind 1, above), whose balls those events named first
 *
 * @param {string} eventsJson a JSON array
 * @param {Buffer} snapshot a kind-1 frame
 * @returns {Buffer}
 */
export function encodeRoomFrame (eventsJson, snapshot) {
  const length = Buffer.byteLength(eventsJson)
  const buffer = Buffer.allocUnsafe(5 + length + snapshot.length)
  buffer[0] = ROOM_FRAME_KIND
  buffer.writeUInt32LE(length, 1)
  buffer.write(eventsJson, 5, length, 'utf8')
  snapshot.copy(buffer, 5 + length)
  return buffer
}

/**
 * Splits a room frame (kind 2) into its events and snapshot frame; a kind-1
 * frame comes back with no events.
 * @param {Uint8Array} bytes
 * @returns {{ events: object[], snapshot: Uint8Array }}
 */
export function splitRoomFrame (bytes) {
  if (bytes[0] !== ROOM_FRAME_KIND) return { events: [], snapshot: bytes }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
  const length = view.getUint32(1, true)
  const events = JSON.parse(new TextDecoder().decode(bytes.subarray(5, 5 + length)))
  return { events, snapshot: bytes.subarray(5 + length) }
}
