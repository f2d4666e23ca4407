/**
 * The browser's side of the wire format (server/rooms/snapshot-codec.js
 * documents the layout and is the reference): binary snapshot frames and
 * room ids.
 */

export const SNAPSHOT_KIND = 1
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

/** @param {string} id @returns {{ rows: number, risk: string } | null} */
export function parseRoomId (id) {
  const match = /^(\d+)-(low|medium|high)$/.exec(id ?? '')
  if (!match) return null
  const rows = Number(match[1])
  return ROWS.includes(rows) ? { rows, risk: match[2] } : null
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
