import { WebSocket } from 'ws'

/**
 * Batches the WebSocket messages one connection is sent during one turn of
 * the event loop into one write, made after the turn. A tick sends its
 * rooms' frames, and the group commit that runs right after it (same turn,
 * in microtasks) the `dropped`/`settled` events: written one by one each
 * would be its own write() system call, the largest single cost of the
 * process under load (see loadtest/RESULTS.md). Each connection's messages
 * wait in its own queue (TurnWriter); a setImmediate writes the queues
 * after the turn's microtasks, each as one buffer: the messages' framed
 * bytes (outgoing-message.js) joined, handed to the socket in one call.
 * Nothing is corked: Node's stream buffering around a cork cost 1.5 µs of
 * the 3.6 µs of user time a frame took to 3,000 loopback sockets, against
 * 2.0 written this way (the kernel's 9 µs the same).
 *
 * At most FLUSH_CHUNK connections are written per turn: with thousands of
 * players a tick's frames take several milliseconds of write() calls, and
 * written in one go they would hold the next tick behind them (the tick
 * lag). The rest are written in the following turns, in the order their
 * first message came, so a tick that falls due runs between two chunks. A
 * connection waits for at most the chunks ahead of it; what it is sent
 * meanwhile joins its queue, so its messages keep their order.
 *
 * What ws writes itself (pings, pongs, a close frame) does not wait here:
 * a connection writes its queue before it closes (Connection.close), so
 * its last messages go before the close frame; anything queued for a socket
 * no longer open when its turn comes is dropped, as ws.send drops a message
 * sent after close. Backpressure counts the queue: `queuedBytes` beside
 * the socket's `bufferedAmount`.
 */

/** Connections written per turn of the event loop (at ~10 µs each, a few ms). */
export const FLUSH_CHUNK = 256

/**
 * Writers with messages waiting, oldest first; those before `next` are
 * written. A flush is scheduled exactly while the list is not empty.
 * @type {TurnWriter[]}
 */
const waiting = []
let next = 0

/**
 * How a Connection writes to its socket, chosen once when the connection
 * is made: a ws WebSocket gets a TurnWriter (its messages written after
 * the turn, framed once, joined); anything else that sends (a test's or a
 * bench's stand-in) is given each message's payload at once.
 * @param {any} socket
 * @returns {{ write: (message: import('./outgoing-message.js').OutgoingMessage) => boolean, flush: () => void, readonly queuedBytes: number }}
 */
export function socketWriter (socket) {
  return socket instanceof WebSocket ? new TurnWriter(socket) : new ImmediateWriter(socket)
}

/** One ws socket's messages of this turn, written together after it. */
export class TurnWriter {
  /** @param {import('ws').WebSocket} socket */
  constructor (socket) {
    this.socket = socket
    /** The TCP socket under it: a framed message is written to it as ws's sender would (Sender#sendFrame). */
    this.raw = socket._socket
    /** The turn's first framed message, or null; most sockets get one a turn. @type {Buffer | null} */
    this.first = null
    /** The turn's later ones, oldest first (kept, emptied: no array a turn). @type {Buffer[]} */
    this.more = []
    this.queuedBytes = 0
    forgetClearedTimer(socket._socket)
  }

  /**
   * Queues a message for the end of the turn; false (nothing queued) when
   * the socket is no longer open.
   * @param {import('./outgoing-message.js').OutgoingMessage} message
   */
  write (message) {
    if (this.socket.readyState !== WebSocket.OPEN) return false
    const wire = message.wire
    this.queuedBytes += wire.length
    if (this.first !== null) this.more.push(wire)
    else {
      this.first = wire
      if (waiting.push(this) === 1) setImmediate(flushWaiting)
    }
    return true
  }

  /** Writes what is queued now (a connection about to close, or its turn came), as one buffer. */
  flush () {
    const first = this.first
    if (first === null) return
    let bytes = first
    if (this.more.length > 0) {
      this.more.unshift(first)
      bytes = Buffer.concat(this.more, this.queuedBytes)
      this.more.length = 0
    }
    this.first = null
    this.queuedBytes = 0
    // The socket may have closed since (the peer left, or ws closed it): dropped, as ws.send drops it.
    if (this.socket.readyState === WebSocket.OPEN) this.raw.write(bytes)
  }
}

/** A stand-in socket's writer: the payload at once, nothing queued. */
class ImmediateWriter {
  constructor (socket) {
    this.socket = socket
    this.queuedBytes = 0
  }

  /** @param {import('./outgoing-message.js').OutgoingMessage} message */
  write (message) {
    this.socket.send(message.payload, { binary: message.binary })
    return true
  }

  flush () {}
}

function flushWaiting () {
  const end = Math.min(waiting.length, next + FLUSH_CHUNK)
  while (next < end) waiting[next++].flush()
  if (next < waiting.length) {
    // Under sustained load the list may never empty: drop the written part once it is most of it.
    if (next > waiting.length >> 1) {
      waiting.copyWithin(0, next)
      waiting.length -= next
      next = 0
    }
    setImmediate(flushWaiting)
    return
  }
  waiting.length = 0
  next = 0
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
