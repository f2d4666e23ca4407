/**
 * Batches the WebSocket frames one connection is sent during one turn of
 * the event loop into one write. A tick sends a room's snapshot, and the
 * group commit that runs right after it (same turn, in microtasks) sends
 * the `dropped`/`settled` events: without batching each frame is its own
 * writev() syscall, the largest single cost of the process under load
 * (see loadtest/RESULTS.md). The first frame of a turn corks the socket;
 * a setImmediate uncorks the corked sockets after the turn's microtasks.
 *
 * At most FLUSH_CHUNK sockets are uncorked per turn: with thousands of
 * players a tick's frames take several milliseconds of writev() calls,
 * and written in one go they would hold the next tick behind them (the
 * tick lag). The rest are written in the following turns, in the order
 * they were corked, so a tick that falls due runs between two chunks.
 * A socket waits for at most the chunks ahead of it; what it is sent
 * meanwhile joins its corked write, so its frames keep their order.
 *
 * Backpressure is unchanged: corked bytes count in `bufferedAmount`.
 */

/** Sockets written per turn of the event loop (at ~10 µs each, a few ms). */
export const FLUSH_CHUNK = 256

/**
 * Corked sockets, oldest first; those before `next` are written. A flush is
 * scheduled exactly while the list is not empty.
 * @type {import('node:net').Socket[]}
 */
const corked = []
let next = 0

/**
 * Corks the TCP socket under a `ws` WebSocket until it is its turn to be
 * written (this turn's end, or a following turn's under load).
 * @param {import('ws').WebSocket} socket
 */
export function holdWritesUntilEndOfTurn (socket) {
  const raw = socket._socket
  if (!raw || raw.writableCorked > 0 || raw.destroyed) return
  raw.cork()
  if (corked.push(raw) === 1) setImmediate(flushWrites)
}

function flushWrites () {
  // ws corks and uncorks around each frame, within the same call: only ours is left.
  const end = Math.min(corked.length, next + FLUSH_CHUNK)
  while (next < end) corked[next++].uncork()
  if (next < corked.length) {
    // Under sustained load the list may never empty: drop the written part once it is most of it.
    if (next > corked.length >> 1) {
      corked.copyWithin(0, next)
      corked.length -= next
      next = 0
    }
    setImmediate(flushWrites)
    return
  }
  corked.length = 0
  next = 0
}
