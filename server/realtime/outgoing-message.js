import { Sender } from 'ws'

/**
 * A message on its way to one socket or many: its payload (JSON text, or a
 * binary frame's bytes) and, made on first need and kept, the whole
 * WebSocket message as its bytes on the wire (RFC 6455 §5.2: FIN, opcode,
 * length, unmasked as a server's frames are), framed by ws's own
 * `Sender.frame` (made static for exactly this, framing a broadcast once:
 * websockets/ws#1016). A room's drop-events or snapshot frame goes to every
 * socket of the room unchanged: `ws.send` would frame it again for each and
 * write header and payload as two buffers (a writev); this is framed once
 * and written as one buffer, one write per socket (write-batcher.js).
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
