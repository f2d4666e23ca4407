import { Sender, WebSocket } from 'ws'

/**
 * A message on its way to one socket or many: its payload (JSON text, or a
 * binary frame's bytes) and, made on first need and kept, the whole
 * WebSocket message as its bytes on the wire (RFC 6455 §5.2: FIN, opcode,
 * length, unmasked as a server's frames are), framed by ws's own
 * `Sender.frame` (made static for exactly this, framing a broadcast once:
 * websockets/ws#1016). A room's drop-events or snapshot frame goes to every
 * socket of the room unchanged: `ws.send` would frame it again for each and
 * write header and payload as two buffers (a writev); this is framed once
 * and written as one buffer, one write per socket.
 */
export class OutgoingMessage {
  /** @param {string | Uint8Array} payload */
  constructor (payload) {
    this.payload = payload
    /** @type {Buffer | null} */
    this._wire = null
  }

  get binary () { return typeof this.payload !== 'string' }

  /** The whole message as written to a socket. */
  get wire () {
    if (this._wire === null) {
      const payload = this.payload
      this._wire = typeof payload === 'string'
        ? framed(Buffer.from(payload), TEXT)
        : framed(Buffer.from(payload.buffer, payload.byteOffset, payload.byteLength), BINARY)
    }
    return this._wire
  }
}

/** What the server's WebSocketServer is created with besides its limits: no compression, so a message can be framed once for every socket. */
export const WEBSOCKET_OPTIONS = Object.freeze({ perMessageDeflate: false })

const BINARY = Object.freeze({ fin: true, rsv1: false, opcode: 0x02, mask: false, readOnly: true })
const TEXT = Object.freeze({ fin: true, rsv1: false, opcode: 0x01, mask: false, readOnly: true })

function framed (data, options) {
  const [header, body] = Sender.frame(data, options)
  return body === undefined ? header : Buffer.concat([header, body], header.length + body.length)
}

/**
 * How a Connection writes an OutgoingMessage to its socket, chosen once
 * when the connection is made: a ws WebSocket is handed the framed bytes
 * (its sender writes a frame at once: the server's sockets never compress,
 * WEBSOCKET_OPTIONS, and never send Blobs, so this keeps the socket's order
 * and counts in its `bufferedAmount`); anything else that sends (a test's
 * or a bench's stand-in) is given the payload.
 * @param {any} socket
 * @returns {(message: OutgoingMessage) => boolean} false: nothing written, the socket is no longer open
 */
export function socketWriter (socket) {
  if (socket instanceof WebSocket) {
    forgetClearedTimer(socket._socket)
    return (message) => {
      if (socket.readyState !== WebSocket.OPEN) return false
      socket._sender.sendFrame([message.wire])
      return true
    }
  }
  return (message) => {
    socket.send(message.payload, { binary: message.binary })
    return true
  }
}

/**
 * ws clears the HTTP socket's idle timeout when it takes the socket over
 * (`setTimeout(0)`), but Node keeps the cleared timer on the socket to reuse
 * it, and then refreshes that dead timer on every read and every write (a
 * trip through the timer list for nothing: about 2% of the server's CPU in
 * a seeds load test). Nothing sets a timeout on an upgraded socket again;
 * should anything, Node creates a new timer.
 * @param {import('node:net').Socket | undefined} raw
 */
function forgetClearedTimer (raw) {
  if (!raw || raw.timeout !== 0) return
  for (const key of Object.getOwnPropertySymbols(raw)) {
    if (key.description === 'timeout' && raw[key] !== null && typeof raw[key] === 'object' && raw[key]._idleTimeout === -1) raw[key] = null
  }
}
