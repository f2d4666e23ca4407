/**
 * Throws away what a socket closed for abuse has received but not yet
 * parsed. ws parses every byte a paused socket has buffered when it closes
 * (its socketOnClose: "any possible buffered data will be read as a single
 * chunk"), so a flooder cut off with a full receive buffer still cost ~2 ms
 * of frames at its close: 64 of them, the event loop for 150 ms. Its frames
 * are no longer wanted: they are dropped unread. Uses ws's `_socket` (the
 * net.Socket it wraps), which has no public accessor.
 * @param {import('ws').WebSocket} websocket
 */
export function discardUnread (websocket) {
  const socket = /** @type {any} */ (websocket)._socket
  if (!socket) return
  // read() hands what it returns to the 'data' listeners (ws's parser): none any more.
  socket.removeAllListeners('data')
  if (socket.readableLength > 0) socket.read(socket.readableLength)
}
