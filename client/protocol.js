/**
 * The browser's side of the wire format (server/rooms/snapshot-codec.js
 * documents the layout and is the reference): binary snapshot and room
 * frames, room ids and the socket URL.
 */

export const SNAPSHOT_KIND = 1
export const ROOM_FRAME_KIND = 2
const POSITION_BITS = 11
const POSITION_MASK = (1 << POSITION_BITS) - 1
const POSITION_STEPS_PER_PX = 2
const HEADER_BYTES = 7

/**
 * @typedef {object} Snapshot
 * @property {number} tick the room tick the positions belong to
 * @property {Int32Array} slots present slots, ascending
 * @property {Float32Array} xs x per present slot (px, 0.5 px steps)
 * @property {Float32Array} ys y per present slot
 */

/**
 * Splits a room frame (kind 2: the other players' events of the snapshot
 * period, then a snapshot frame) into its events and the snapshot frame. A
 * snapshot frame (kind 1) comes back whole with no events; anything else,
 * or a truncated frame, gives null.
 * @param {ArrayBuffer} buffer
 * @returns {{ events: object[], snapshot: ArrayBuffer } | null}
 */
export function splitRoomFrame (buffer) {
  if (buffer.byteLength < 1) return null
  const view = new DataView(buffer)
  const kind = view.getUint8(0)
  if (kind === SNAPSHOT_KIND) return { events: [], snapshot: buffer }
  if (kind !== ROOM_FRAME_KIND || buffer.byteLength < 5) return null
  const length = view.getUint32(1, true)
  if (buffer.byteLength < 5 + length) return null
  let events
  try {
    events = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 5, length)))
  } catch {
    return null
  }
  return Array.isArray(events) ? { events, snapshot: buffer.slice(5 + length) } : null
}

/**
 * Decodes a snapshot frame; null for a frame of another kind or a truncated one.
 * @param {ArrayBuffer} buffer
 * @returns {Snapshot | null}
 */
export function decodeSnapshot (buffer) {
  if (buffer.byteLength < HEADER_BYTES) return null
  const view = new DataView(buffer)
  if (view.getUint8(0) !== SNAPSHOT_KIND) return null
  const tick = view.getUint32(1, true)
  const span = view.getUint16(5, true)
  const maskBytes = (span + 7) >> 3
  if (buffer.byteLength < HEADER_BYTES + maskBytes) return null
  const bytes = new Uint8Array(buffer)
  let count = 0
  for (let i = 0; i < maskBytes; i++) {
    for (let b = bytes[HEADER_BYTES + i]; b !== 0; b &= b - 1) count++
  }
  if (buffer.byteLength < HEADER_BYTES + maskBytes + ((count * 2 * POSITION_BITS + 7) >> 3)) return null
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
    const value = bits & POSITION_MASK
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

export const ROWS = [8, 9, 10, 11, 12, 13, 14, 15, 16]
export const RISKS = ['low', 'medium', 'high']

/** @param {number} rows @param {string} risk */
export function roomIdOf (rows, risk) {
  return `${rows}-${risk}`
}

/** Rooms per board (server/rooms/room-id.js): `16-medium`, then `16-medium.2` … `16-medium.8`. */
export const ROOM_INSTANCES = 8

/** @param {string} id @returns {{ rows: number, risk: string, instance: number } | null} */
export function parseRoomId (id) {
  const match = /^(\d+)-(low|medium|high)(?:\.([2-9]\d*))?$/.exec(id ?? '')
  if (!match) return null
  const rows = Number(match[1])
  const instance = match[3] === undefined ? 1 : Number(match[3])
  return ROWS.includes(rows) && instance <= ROOM_INSTANCES ? { rows, risk: match[2], instance } : null
}

/**
 * The game socket's URL for a session token. `base` is where the socket
 * lives: the page's own address (its directory, so a page served under a
 * prefix such as /n/1/ talks to that process) or, after E_WRONG_NODE, the
 * `owner` the server named. Only http(s) bases are followed; anything else
 * gives null.
 * @param {string} base an absolute http(s) URL
 * @param {string} token
 * @returns {string | null}
 */
export function socketUrl (base, token) {
  let url
  try {
    url = new URL(base)
  } catch {
    return null
  }
  if (url.protocol !== 'http:' && url.protocol !== 'https:') return null
  url.protocol = url.protocol === 'https:' ? 'wss:' : 'ws:'
  url.pathname = url.pathname.replace(/\/?$/, '/') + 'ws'
  url.search = `?token=${encodeURIComponent(token)}`
  url.hash = ''
  return url.href
}
