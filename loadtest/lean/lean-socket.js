/**
 * A minimal WebSocket client (RFC 6455) on a raw `node:net` socket, for the
 * lean load generator: what one simulated player needs and nothing else.
 * Measured on the development machine against a bare `ws` server sending
 * 190-byte frames every 50 ms, 1,000 sockets on one core (CPU per frame
 * received): `ws`'s own client 11.8–12.6 µs (6.1–6.5 µs of it in user
 * space); a `node:net` reader with 'data' events 8.5–9.8 µs (3.0–4.0 µs
 * user); with `onread` into one shared buffer, as here, 7.8–8.3 µs (2.0 µs
 * user); a small Go client (net.Conn + bufio) 8.9–10.7 µs. The rest, about
 * 6 µs, is the kernel's read() of one loopback TCP segment (and the ACK it
 * sends), which every client in every language pays once per frame here.
 * See loadtest/RESULTS.md.
 *
 * - The handshake is checked (101, `Sec-WebSocket-Accept` = SHA-1 of the key
 *   and the RFC's GUID); no extension is asked for (no permessage-deflate).
 * - Server frames must be unmasked; control frames (ping, pong, close) are
 *   answered as the RFC says (ping → pong with the same payload, close →
 *   close), fragmented messages are reassembled.
 * - Every frame this client sends is masked (a fresh random key per frame).
 * - A protocol violation (masked server frame, unknown opcode, reserved
 *   bits, a control frame over 125 bytes or fragmented) ends the socket with
 *   `onClose(1002)`; a message over `maxPayload` with 1009.
 *
 * Only what the caller asks for is decoded: text frames become strings,
 * binary frames are handed over as (buffer, start, end) without a copy when
 * they arrive in one piece.
 */
import net from 'node:net'
import { createHash, randomBytes, randomFillSync } from 'node:crypto'

const GUID = '258EAFA5-E914-47DA-95CA-C5AB0DC85B11'
const OP_CONTINUATION = 0
const OP_TEXT = 1
const OP_BINARY = 2
const OP_CLOSE = 8
const OP_PING = 9
const OP_PONG = 10
const DEFAULT_MAX_PAYLOAD = 16 * 1024 * 1024
const HANDSHAKE_TIMEOUT_MS = 30_000
const MAX_HANDSHAKE_BYTES = 16 * 1024
/** Read buffer of every LeanSocket in this thread (reads are synchronous: one socket at a time). */
const sharedReadBuffer = Buffer.allocUnsafe(256 * 1024)
/** The close code reported when the TCP connection ended without a close frame (RFC 6455 §7.1.5). */
export const CLOSE_ABNORMAL = 1006
export const CLOSE_PROTOCOL_ERROR = 1002
export const CLOSE_TOO_BIG = 1009

/** The `Sec-WebSocket-Accept` a server must answer to `key`. @param {string} key */
export function acceptKey (key) {
  return createHash('sha1').update(key + GUID).digest('base64')
}

/**
 * Builds one masked client frame.
 * @param {number} opcode @param {Buffer} payload
 * @param {Buffer} [mask] 4 bytes (random when not given)
 * @returns {Buffer}
 */
export function encodeClientFrame (opcode, payload, mask = randomBytes(4)) {
  const length = payload.length
  const head = length < 126 ? 2 : length < 65536 ? 4 : 10
  const frame = Buffer.allocUnsafe(head + 4 + length)
  frame[0] = 0x80 | opcode
  if (length < 126) {
    frame[1] = 0x80 | length
  } else if (length < 65536) {
    frame[1] = 0x80 | 126
    frame.writeUInt16BE(length, 2)
  } else {
    frame[1] = 0x80 | 127
    frame.writeUInt32BE(0, 2)
    frame.writeUInt32BE(length, 6)
  }
  mask.copy(frame, head, 0, 4)
  for (let i = 0; i < length; i++) frame[head + 4 + i] = payload[i] ^ mask[i & 3]
  return frame
}

/**
 * Incremental parser of server → client frames. Feed it the socket's
 * chunks in order; it calls `onFrame(fin, opcode, buffer, start, end)` for
 * each complete frame (the bytes stay valid only during the call) or
 * `onViolation(code, reason)` once and then ignores the rest.
 */
export class ServerFrameParser {
  /**
   * @param {(fin: boolean, opcode: number, buffer: Buffer, start: number, end: number) => void} onFrame
   * @param {(code: number, reason: string) => void} onViolation
   * @param {number} [maxPayload]
   */
  constructor (onFrame, onViolation, maxPayload = DEFAULT_MAX_PAYLOAD) {
    this.onFrame = onFrame
    this.onViolation = onViolation
    this.maxPayload = maxPayload
    /** Bytes of an incomplete frame carried over from the previous chunk. */
    this.rest = null
    this.failed = false
  }

  /**
   * @param {Buffer} chunk read from the socket; it may be reused once this
   *   returns (what is left of an incomplete frame is copied)
   * @param {number} [length] bytes of `chunk` that were read
   */
  push (chunk, length = chunk.length) {
    if (this.failed) return
    let buffer = chunk
    let size = length
    if (this.rest !== null) {
      buffer = Buffer.concat([this.rest, chunk.subarray(0, length)])
      size = buffer.length
      this.rest = null
    }
    let offset = 0
    while (size - offset >= 2) {
      const b0 = buffer[offset]
      const b1 = buffer[offset + 1]
      if ((b0 & 0x70) !== 0) return this._fail(CLOSE_PROTOCOL_ERROR, 'reserved bits set (no extension was negotiated)')
      if ((b1 & 0x80) !== 0) return this._fail(CLOSE_PROTOCOL_ERROR, 'masked frame from the server')
      const opcode = b0 & 0x0f
      let length = b1 & 0x7f
      let head = 2
      if (length === 126) {
        if (size - offset < 4) break
        length = (buffer[offset + 2] << 8) | buffer[offset + 3]
        head = 4
      } else if (length === 127) {
        if (size - offset < 10) break
        const high = buffer.readUInt32BE(offset + 2)
        if (high > 0x1fffff) return this._fail(CLOSE_TOO_BIG, 'frame too big')
        length = high * 4294967296 + buffer.readUInt32BE(offset + 6)
        head = 10
      }
      if (length > this.maxPayload) return this._fail(CLOSE_TOO_BIG, `frame of ${length} bytes over maxPayload`)
      if (opcode >= OP_CLOSE) {
        if (opcode > OP_PONG) return this._fail(CLOSE_PROTOCOL_ERROR, `unknown control opcode ${opcode}`)
        if (length > 125 || (b0 & 0x80) === 0) return this._fail(CLOSE_PROTOCOL_ERROR, 'control frame over 125 bytes or fragmented')
      } else if (opcode > OP_BINARY) {
        return this._fail(CLOSE_PROTOCOL_ERROR, `unknown data opcode ${opcode}`)
      }
      const end = offset + head + length
      if (end > size) break
      this.onFrame((b0 & 0x80) !== 0, opcode, buffer, offset + head, end)
      if (this.failed) return
      offset = end
    }
    if (offset < size) this.rest = Buffer.from(buffer.subarray(offset, size))
  }

  _fail (code, reason) {
    this.failed = true
    this.rest = null
    this.onViolation(code, reason)
  }
}

/**
 * @typedef {object} LeanSocketHandlers
 * @property {() => void} [onOpen]
 * @property {(text: string, at: number) => void} onText a whole text message; `at` = performance.now() when its last chunk arrived
 * @property {(buffer: Buffer, start: number, end: number, at: number) => void} onBinary a whole binary message (valid during the call)
 * @property {(code: number, reason: string) => void} onClose once: the server's close code, 1006 when the connection just ended, 1002/1009 for a violation
 * @property {(error: Error) => void} [onError] a socket or handshake error (onClose follows)
 */

/** One client WebSocket over `node:net`. */
export class LeanSocket {
  /**
   * @param {{ host: string, port: number, path: string, maxPayload?: number }} target
   * @param {LeanSocketHandlers} handlers
   */
  constructor ({ host, port, path, maxPayload = DEFAULT_MAX_PAYLOAD }, handlers) {
    this.handlers = handlers
    this.open = false
    this.closed = false
    this.closeSent = false
    /** Payload bytes of the fragments of a message being reassembled, and its opcode. */
    this.fragments = null
    this.fragmentOpcode = 0
    this.fragmentBytes = 0
    this.maxPayload = maxPayload
    this.key = randomBytes(16).toString('base64')
    this.handshake = ''
    this.parser = new ServerFrameParser((fin, opcode, buffer, start, end) => this._frame(fin, opcode, buffer, start, end), (code, reason) => this._violation(code, reason), maxPayload)
    /** performance.now() of the chunk being parsed. */
    this.at = 0
    this.mask = Buffer.alloc(4)
    // onread: the socket reads into one buffer shared by every LeanSocket of
    // the thread and calls back directly, without a stream 'data' event or
    // a Buffer per read (1–2 µs per frame less, measured).
    const socket = net.connect({ host, port, noDelay: true, onread: { buffer: sharedReadBuffer, callback: (nread, buffer) => this._read(nread, buffer) } })
    this.socket = socket
    socket.setTimeout(HANDSHAKE_TIMEOUT_MS, () => {
      if (!this.open) socket.destroy(new Error(`no WebSocket handshake within ${HANDSHAKE_TIMEOUT_MS} ms`))
    })
    socket.once('connect', () => {
      socket.write(`GET ${path} HTTP/1.1\r\nHost: ${host}:${port}\r\nConnection: Upgrade\r\nUpgrade: websocket\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Key: ${this.key}\r\n\r\n`)
    })
    socket.on('error', (error) => {
      if (!this.closed && this.handlers.onError) this.handlers.onError(error)
    })
    socket.on('close', () => this._ended(CLOSE_ABNORMAL, 'connection ended without a close frame'))
  }

  _read (nread, buffer) {
    this.at = performance.now()
    if (this.open) this.parser.push(buffer, nread)
    else this._handshakeData(buffer, nread)
  }

  _handshakeData (buffer, nread) {
    this.handshake += buffer.toString('latin1', 0, nread)
    const end = this.handshake.indexOf('\r\n\r\n')
    if (end === -1) {
      if (this.handshake.length > MAX_HANDSHAKE_BYTES) this.socket.destroy(new Error('handshake answer too long'))
      return
    }
    const lines = this.handshake.slice(0, end).split('\r\n')
    const status = /^HTTP\/1\.1 (\d{3})/.exec(lines[0])
    const headers = new Map()
    for (const line of lines.slice(1)) {
      const colon = line.indexOf(':')
      if (colon > 0) headers.set(line.slice(0, colon).trim().toLowerCase(), line.slice(colon + 1).trim())
    }
    if (!status || status[1] !== '101') return this._refused(`handshake answered ${lines[0]}`, status ? Number(status[1]) : 0)
    if (headers.get('sec-websocket-accept') !== acceptKey(this.key)) return this._refused('bad Sec-WebSocket-Accept', 101)
    if (headers.has('sec-websocket-extensions')) return this._refused('server chose an extension that was not offered', 101)
    const rest = Buffer.from(this.handshake.slice(end + 4), 'latin1')
    this.handshake = ''
    this.open = true
    this.socket.setTimeout(0)
    if (this.handlers.onOpen) this.handlers.onOpen()
    if (rest.length > 0) this.parser.push(rest)
  }

  _refused (reason, status) {
    if (this.handlers.onError) this.handlers.onError(Object.assign(new Error(reason), { status }))
    this.socket.destroy()
  }

  _frame (fin, opcode, buffer, start, end) {
    if (opcode >= OP_CLOSE) return this._control(opcode, buffer, start, end)
    if (opcode === OP_CONTINUATION) {
      if (this.fragments === null) return this._violation(CLOSE_PROTOCOL_ERROR, 'continuation frame without a first fragment')
    } else if (this.fragments !== null) {
      return this._violation(CLOSE_PROTOCOL_ERROR, 'new message before the last one ended')
    } else if (fin) {
      // The common case: a whole message in one frame.
      if (opcode === OP_TEXT) this.handlers.onText(buffer.toString('utf8', start, end), this.at)
      else this.handlers.onBinary(buffer, start, end, this.at)
      return
    } else {
      this.fragments = []
      this.fragmentOpcode = opcode
      this.fragmentBytes = 0
    }
    this.fragmentBytes += end - start
    if (this.fragmentBytes > this.maxPayload) return this._violation(CLOSE_TOO_BIG, 'message over maxPayload')
    this.fragments.push(Buffer.from(buffer.subarray(start, end)))
    if (!fin) return
    const whole = Buffer.concat(this.fragments)
    const kind = this.fragmentOpcode
    this.fragments = null
    if (kind === OP_TEXT) this.handlers.onText(whole.toString('utf8'), this.at)
    else this.handlers.onBinary(whole, 0, whole.length, this.at)
  }

  _control (opcode, buffer, start, end) {
    if (opcode === OP_PING) {
      this._write(OP_PONG, Buffer.from(buffer.subarray(start, end)))
    } else if (opcode === OP_CLOSE) {
      const code = end - start >= 2 ? buffer.readUInt16BE(start) : 1005
      const reason = end - start > 2 ? buffer.toString('utf8', start + 2, end) : ''
      if (!this.closeSent) {
        this.closeSent = true
        this._write(OP_CLOSE, code === 1005 ? Buffer.alloc(0) : Buffer.from(buffer.subarray(start, start + 2)))
      }
      this._ended(code, reason)
      this.socket.end()
    }
  }

  _violation (code, reason) {
    this.parser.failed = true
    if (!this.closeSent) {
      this.closeSent = true
      const payload = Buffer.alloc(2)
      payload.writeUInt16BE(code)
      this._write(OP_CLOSE, payload)
    }
    this._ended(code, reason)
    this.socket.end()
    setTimeout(() => this.socket.destroy(), 1000).unref()
  }

  _ended (code, reason) {
    if (this.closed) return
    this.closed = true
    this.open = false
    this.handlers.onClose(code, reason)
  }

  _write (opcode, payload) {
    if (this.socket.destroyed || !this.socket.writable) return
    randomFillSync(this.mask)
    this.socket.write(encodeClientFrame(opcode, payload, this.mask))
  }

  /** Sends a text message (ignored once closing). @param {string} text */
  sendText (text) {
    if (!this.open || this.closeSent) return
    this._write(OP_TEXT, Buffer.from(text, 'utf8'))
  }

  /**
   * Starts the closing handshake (the server answers with its close frame,
   * then onClose runs with the code); the TCP socket is destroyed if the
   * answer does not come within `graceMs`.
   * @param {number} [code] @param {number} [graceMs]
   */
  close (code = 1000, graceMs = 5000) {
    if (this.closed) return
    if (!this.open) {
      this.socket.destroy()
      return
    }
    if (!this.closeSent) {
      this.closeSent = true
      const payload = Buffer.alloc(2)
      payload.writeUInt16BE(code)
      this._write(OP_CLOSE, payload)
    }
    setTimeout(() => this.socket.destroy(), graceMs).unref()
  }
}
