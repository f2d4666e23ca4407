/**
 * Batches the WebSocket frames one connection is sent during one turn of
 * the event loop into one write. A tick sends a room's snapshot, and the
 * group commit that runs right after it (same turn, in microtasks) sends
 * the `dropped`/`settled` events: without batching each frame is its own
 * writev() syscall, the largest single cost of the process under load
 * (see loadtest/RESULTS.md). The first frame of a turn corks the socket;
 * one setImmediate per turn uncorks every corked socket, after the turn's
 * microtasks, so nothing waits longer than the current turn.
 *
 * Backpressure is unchanged: corked bytes count in `bufferedAmount`.
 */

/** @type {import('node:net').Socket[]} */
const corked = []
let flushScheduled = false

/**
 * Corks the TCP socket under a `ws` WebSocket until the end of this turn.
 * @param {import('ws').WebSocket} socket
 */
export function holdWritesUntilEndOfTurn (socket) {
  const raw = socket._socket
  if (!raw || raw.writableCorked > 0 || raw.destroyed) return
  raw.cork()
  corked.push(raw)
  if (!flushScheduled) {
    flushScheduled = true
    setImmediate(flushWrites)
  }
}

function flushWrites () {
  flushScheduled = false
  // ws corks and uncorks around each frame, within the same call: only ours is left.
  for (let i = 0; i < corked.length; i++) corked[i].uncork()
  corked.length = 0
}
