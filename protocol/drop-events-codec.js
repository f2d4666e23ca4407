import { ENGINE_VERSIONS } from '../engine/version.js'
import { StateHasher } from '../engine/state-hasher.js'

/**
 * The binary frame of the `seeds` delivery mode, one module for the server
 * (which encodes it) and the browser and load tools (which decode it):
 * served to the page at /protocol/ as it is in the repository.
 *
 * A socket that joined with `delivery: "seeds"` gets no position frames: the
 * page simulates every ball itself from its drop seed (the engine gives the
 * same bits everywhere). Besides its own JSON replies it gets one kind of
 * binary frame, the drop-events frame, built once per room and sent as the
 * same bytes to every seeds socket in it (a socket's own messages appended
 * to its copy: the owner's section below; a socket whose own drops are all
 * a frame holds does not get it, unless with its owner's section):
 *
 * - at most every EVENT_EVERY ticks (joined.eventEvery = 60 / EVENT_HZ), with
 *   the drops announced in the room since the previous frame, oldest first;
 * - or, when no drop was announced, at most every CHECK_EVERY ticks
 *   (joined.checkEvery, 2 s) while balls are in flight, with no events: a
 *   desync check alone.
 * A room with nothing new and no ball in flight sends nothing.
 *
 * Little-endian throughout:
 *
 *   offset  size   field
 *   0       1      kind = 3 (DROP_EVENTS_KIND)
 *   1       4      tick, uint32: the room tick this frame was built at (after that tick's step)
 *   5       4      hash word 1, uint32 } the flight hash at `tick` (below); as text, the 16 hex
 *   9       4      hash word 2, uint32 } digits hex8(word 1) + hex8(word 2)
 *   13      2      N, uint16: number of events
 *   15      64·N   the events, oldest first
 *   15+64·N rest   the receiver's own messages (optional, this socket's copy only): ASCII text
 *                  of a JSON array of the server's JSON messages for this player, oldest first
 *                  (today: its `settled` messages in this room, each with its balance), to be
 *                  handled after the events as if each had come on its own. Absent (the frame
 *                  ends after the events) when there are none.
 *
 * One event (64 bytes), another player's drop as `dropped` announces it:
 *
 *   offset  size   field
 *   0       8      dropId, uint64 (below 2^53)
 *   8       8      bet, uint64 (below 2^53), whole credits
 *   16      4      startTick, uint32: the room tick at which the ball was released
 *   20      2      slot, uint16: the ball's small per-room number (as in snapshots and `joined`)
 *   22      1      engine, uint8: index of the drop's engine version in ENGINE_VERSIONS
 *                  (oldest first, append-only; also sent as joined.engineVersions)
 *   23      1      flags: bit 0 set = the player id is not 16 hex digits and the tag is zero
 *   24      8      player tag: the player id's 16 hex digits as 8 bytes, in order
 *   32      32     dropSeed: its 64 hex digits as 32 bytes, in order
 *
 * A ball of startTick s is at the state the engine reaches after (t − s)
 * steps of a DropSimulator into which it was added alone: balls do not
 * collide, so a drop's path depends on its seed and the board only. The
 * full facts for verifying it (server seed hash, client seed, nonce, and
 * once landed the bucket, payout and state hash) are served to whoever has
 * its seed, at its share link GET /api/share/:dropId/:token (the token is
 * the seed's, protocol/share-token.js).
 *
 * Flight hash: the balls in flight at `tick` that the room has announced
 * (every one was named in `joined.balls`, a `dropped` reply or an event
 * frame no later than this frame), in ascending slot order, hashed with the
 * engine's StateHasher (engine/state-hasher.js, 64-bit, over exact IEEE-754
 * bits):
 *
 *   reset(); addInt32(tick)
 *   for each ball, slots ascending:
 *     addInt32(slot); addFloat64(x); addFloat64(y); addFloat64(vx); addFloat64(vy)
 *   digestHex()
 *
 * A ball that landed in a step up to `tick` is not in flight (the engine
 * destroys it in the step it lands). FlightHasher below does exactly this.
 * A page whose own hash differs has desynchronised: it switches the room to
 * snapshots (join again with delivery "snapshots") and reports it.
 *
 * A batch may name a drop the receiver already knows (from `joined.balls`
 * just before it, or its own `dropped` reply): match on dropId and skip it.
 */
export const DROP_EVENTS_KIND = 3
export const DROP_EVENT_BYTES = 64
export const DROP_EVENTS_HEADER_BYTES = 15
export const MAX_EVENTS_PER_FRAME = 0xffff
const FLAG_PLAYER_NOT_HEX = 1

const HEX16 = /^[0-9a-f]{16}$/

/**
 * @typedef {object} DropEvent
 * @property {number} dropId @property {number} bet whole credits
 * @property {number} startTick @property {number} slot
 * @property {string} engineVersion @property {string} player 16 hex digits, or '' (flag bit 0)
 * @property {string} dropSeed 64 hex digits
 */

/**
 * @typedef {object} DropEventsFrame
 * @property {number} tick @property {string} hash 16 hex digits (FlightHasher)
 * @property {DropEvent[]} events
 * @property {object[]} own this socket's own messages (the owner's section), oldest first; [] when none
 */

/**
 * @param {number} tick
 * @param {string} hash 16 hex digits, from FlightHasher.digest()
 * @param {ArrayLike<{ id: number, bet: number, startTick: number, slot: number, engineVersion: string, playerId: string, dropSeed: string }>} drops oldest first
 * @returns {Uint8Array}
 */
export function encodeDropEvents (tick, hash, drops) {
  if (drops.length > MAX_EVENTS_PER_FRAME) throw new RangeError('too many events for one frame')
  if (!HEX16.test(hash)) throw new RangeError('the flight hash must be 16 hex digits')
  const bytes = new Uint8Array(DROP_EVENTS_HEADER_BYTES + DROP_EVENT_BYTES * drops.length)
  const view = new DataView(bytes.buffer)
  bytes[0] = DROP_EVENTS_KIND
  view.setUint32(1, tick >>> 0, true)
  view.setUint32(5, parseInt(hash.slice(0, 8), 16), true)
  view.setUint32(9, parseInt(hash.slice(8, 16), 16), true)
  view.setUint16(13, drops.length, true)
  for (let i = 0; i < drops.length; i++) {
    const drop = drops[i]
    const at = DROP_EVENTS_HEADER_BYTES + i * DROP_EVENT_BYTES
    const engine = ENGINE_VERSIONS.indexOf(drop.engineVersion)
    if (engine < 0) throw new RangeError(`unknown engine version ${drop.engineVersion}`)
    if (drop.slot > 0xffff) throw new RangeError('slot above 65535')
    if (!writeHex(bytes, at + 32, drop.dropSeed, 64)) throw new RangeError('a drop seed must be 64 hex digits')
    setUint53(view, at, drop.id)
    setUint53(view, at + 8, drop.bet)
    view.setUint32(at + 16, drop.startTick >>> 0, true)
    view.setUint16(at + 20, drop.slot, true)
    bytes[at + 22] = engine
    if (!writeHex(bytes, at + 24, drop.playerId, 16)) {
      bytes.fill(0, at + 24, at + 32)
      bytes[at + 23] = FLAG_PLAYER_NOT_HEX
    }
  }
  return bytes
}

/**
 * A room's frame with one socket's own messages after its events (the
 * owner's section of the header comment): a copy, the room's bytes first.
 * Non-ASCII characters are written as \u escapes, so every decoder can read
 * the section byte by byte.
 * @param {Uint8Array} frame from encodeDropEvents()
 * @param {string[]} messages JSON texts of this socket's messages, oldest first
 * @returns {Uint8Array}
 */
export function withOwnMessages (frame, messages) {
  let text = `[${messages.join(',')}]`
  if (NON_ASCII.test(text)) text = text.replace(NON_ASCII_ALL, (c) => `\\u${c.charCodeAt(0).toString(16).padStart(4, '0')}`)
  const bytes = new Uint8Array(frame.length + text.length)
  bytes.set(frame)
  // ASCII now, so its UTF-8 is one byte per character.
  asciiEncoder ??= new TextEncoder()
  asciiEncoder.encodeInto(text, bytes.subarray(frame.length))
  return bytes
}

const NON_ASCII = /[^\x00-\x7f]/
const NON_ASCII_ALL = /[^\x00-\x7f]/g
// Made on first use: a reader of frames on a plain JavaScript engine (no TextEncoder) never needs it.
let asciiEncoder = null

/**
 * Decodes a drop-events frame; null for a frame of another kind, a
 * truncated one, one naming an engine version this module does not know,
 * or one whose own messages are not a JSON array.
 * @param {Uint8Array | ArrayBuffer} frame
 * @returns {DropEventsFrame | null}
 */
export function decodeDropEvents (frame) {
  const bytes = frame instanceof Uint8Array ? frame : new Uint8Array(frame)
  const count = checkedEventCount(bytes)
  if (count < 0) return null
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
  const events = new Array(count)
  for (let i = 0; i < count; i++) {
    const at = DROP_EVENTS_HEADER_BYTES + i * DROP_EVENT_BYTES
    events[i] = {
      dropId: getUint53(view, at),
      bet: getUint53(view, at + 8),
      startTick: view.getUint32(at + 16, true),
      slot: view.getUint16(at + 20, true),
      engineVersion: ENGINE_VERSIONS[bytes[at + 22]],
      player: playerOf(bytes, at),
      dropSeed: readHex(bytes, at + 32, 32)
    }
  }
  const own = decodeOwnMessages(bytes, DROP_EVENTS_HEADER_BYTES + count * DROP_EVENT_BYTES)
  if (own === null) return null
  return { tick: view.getUint32(1, true), hash: hex8(view.getUint32(5, true)) + hex8(view.getUint32(9, true)), events, own }
}

/**
 * A drop-events frame read for who dropped what, without building its
 * events (no seed or flight-hash text): `onEvent(dropId, player, startTick,
 * tick)` for each event, oldest first (`tick`: the frame's), then the
 * frame's tick and the owner's section.
 * Refuses exactly what decodeDropEvents refuses (null), and then calls
 * `onEvent` for none of its events. For readers that look at every frame of
 * thousands of sockets (the lean load generator), where decoding each event
 * whole is most of their work per frame.
 * @param {Uint8Array} bytes
 * @param {(dropId: number, player: string, startTick: number, tick: number) => void} onEvent player: 16 hex digits, or '' (flag bit 0)
 * @returns {{ tick: number, own: object[] } | null}
 */
export function scanDropEvents (bytes, onEvent) {
  const count = checkedEventCount(bytes)
  if (count < 0) return null
  const own = decodeOwnMessages(bytes, DROP_EVENTS_HEADER_BYTES + count * DROP_EVENT_BYTES)
  if (own === null) return null
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
  const tick = view.getUint32(1, true)
  for (let i = 0; i < count; i++) {
    const at = DROP_EVENTS_HEADER_BYTES + i * DROP_EVENT_BYTES
    onEvent(getUint53(view, at), playerOf(bytes, at), view.getUint32(at + 16, true), tick)
  }
  return { tick, own }
}

/**
 * The number of events of a drop-events frame, or -1 when it is of another
 * kind, shorter than its events, or names an engine version this module
 * does not know.
 * @param {Uint8Array} bytes
 */
function checkedEventCount (bytes) {
  if (bytes.byteLength < DROP_EVENTS_HEADER_BYTES || bytes[0] !== DROP_EVENTS_KIND) return -1
  const count = bytes[13] | (bytes[14] << 8)
  if (bytes.byteLength < DROP_EVENTS_HEADER_BYTES + count * DROP_EVENT_BYTES) return -1
  for (let i = 0; i < count; i++) {
    if (ENGINE_VERSIONS[bytes[DROP_EVENTS_HEADER_BYTES + i * DROP_EVENT_BYTES + 22]] === undefined) return -1
  }
  return count
}

/** An event's player id (16 hex digits), or '' where the server flagged it as not hex. */
function playerOf (bytes, at) {
  return (bytes[at + 23] & FLAG_PLAYER_NOT_HEX) === 0 ? readHex(bytes, at + 24, 8) : ''
}

/**
 * The owner's section of a drop-events frame, from `at` (15 + 64·N) to the
 * end: [] when there is none, null when it is not a JSON array. Exported
 * for readers that count the events without decoding them (the k6 player).
 * @param {Uint8Array} bytes @param {number} at
 * @returns {object[] | null}
 */
export function decodeOwnMessages (bytes, at) {
  if (at === bytes.byteLength) return []
  let text = ''
  for (let i = at; i < bytes.byteLength; i += 4096) text += String.fromCharCode.apply(null, bytes.subarray(i, Math.min(i + 4096, bytes.byteLength)))
  try {
    const messages = JSON.parse(text)
    return Array.isArray(messages) ? messages : null
  } catch {
    return null
  }
}

/**
 * The flight hash of the header comment: begin(tick), add() each ball in
 * ascending slot order, digest(). One instance is reused; adding allocates
 * nothing.
 */
export class FlightHasher {
  constructor () {
    this._hasher = new StateHasher()
    this._lastSlot = -1
  }

  /** @param {number} tick the room tick the states belong to */
  begin (tick) {
    this._hasher.reset().addInt32(tick)
    this._lastSlot = -1
    return this
  }

  /** @param {number} slot @param {number} x @param {number} y @param {number} vx @param {number} vy */
  add (slot, x, y, vx, vy) {
    if (slot <= this._lastSlot) throw new RangeError('balls must be added in ascending slot order')
    this._lastSlot = slot
    this._hasher.addInt32(slot).addFloat64(x).addFloat64(y).addFloat64(vx).addFloat64(vy)
    return this
  }

  /** @returns {string} 16 hex digits */
  digest () {
    return this._hasher.digestHex()
  }
}

function setUint53 (view, at, value) {
  if (!Number.isSafeInteger(value) || value < 0) throw new RangeError(`${value} is not an integer from 0 to 2^53 - 1`)
  view.setUint32(at, value % 0x100000000, true)
  view.setUint32(at + 4, Math.floor(value / 0x100000000), true)
}

function getUint53 (view, at) {
  return view.getUint32(at + 4, true) * 0x100000000 + view.getUint32(at, true)
}

/**
 * Writes `hex` (exactly `digits` lowercase hex digits) as bytes at `at`,
 * with no regular expression or substring per digit (it runs for every
 * event of every frame); false, with some bytes written, when it is not.
 */
function writeHex (bytes, at, hex, digits) {
  if (typeof hex !== 'string' || hex.length !== digits) return false
  for (let i = 0; i < digits; i += 2) {
    const high = hexValue(hex.charCodeAt(i))
    const low = hexValue(hex.charCodeAt(i + 1))
    if ((high | low) < 0) return false
    bytes[at + (i >> 1)] = (high << 4) | low
  }
  return true
}

/** A lowercase hex digit's value, or -1. @param {number} code a UTF-16 code unit */
function hexValue (code) {
  if (code >= 48 && code <= 57) return code - 48
  if (code >= 97 && code <= 102) return code - 87
  return -1
}

/** Every byte's two lowercase hex digits: a frame's seeds are read by table, not by toString(16) per byte. */
const HEX_OF_BYTE = Array.from({ length: 256 }, (_, byte) => (byte < 16 ? '0' : '') + byte.toString(16))

function readHex (bytes, at, length) {
  let text = ''
  for (let i = at; i < at + length; i++) text += HEX_OF_BYTE[bytes[i]]
  return text
}

function hex8 (n) {
  return n.toString(16).padStart(8, '0')
}
