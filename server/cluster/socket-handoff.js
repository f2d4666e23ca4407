/**
 * Hands a WebSocket's TCP connection from the cluster's proxy to the server
 * process that serves it, so the proxy carries no frames (piping every
 * frame through a second process cost about as much CPU as the server's own
 * sending; see loadtest/RESULTS.md). Both ends of the IPC protocol are here:
 *
 *   proxy  handOff(child, socket, head): once it has chosen the process,
 *          it sends the socket itself over the child's IPC channel (Node
 *          passes the file descriptor) with the request head it already
 *          read, rewritten as it would have piped it (X-Forwarded-For set).
 *   server acceptHandedOffSockets(httpServer): puts the head back in front
 *          of the socket and gives the socket to its HTTP server as a new
 *          connection; ws then answers the upgrade as for any client. When
 *          such a socket closes it tells the proxy (its least-connections
 *          count).
 *
 * A WebSocket client sends nothing after its upgrade request until the 101
 * answer, so no byte is in flight while the socket moves.
 */

export const HANDOFF = 'plinko:socket'
export const HANDOFF_CLOSED = 'plinko:socket-closed'

/**
 * Can `child` take sockets (a live IPC channel)?
 * @param {import('node:child_process').ChildProcess | undefined | null} child
 */
export function canHandOff (child) {
  return Boolean(child?.connected)
}

/**
 * Sends `socket` (an HTTP upgrade, its head already read) to `child`.
 * @param {import('node:child_process').ChildProcess} child
 * @param {import('node:net').Socket} socket
 * @param {Buffer} head the request head as the server must read it, and any bytes after it
 * @param {(error: Error) => void} onError the socket could not be sent (it is destroyed)
 */
export function handOff (child, socket, head, onError) {
  child.send({ type: HANDOFF, head: head.toString('base64') }, socket, { keepOpen: false }, (error) => {
    if (!error) return
    socket.destroy()
    onError(error)
  })
}

/**
 * In a server process started with an IPC channel (scripts/cluster.js):
 * serves the sockets the proxy hands over. Does nothing without one.
 * @param {import('node:http').Server} httpServer
 * @param {NodeJS.Process} [proc]
 */
export function acceptHandedOffSockets (httpServer, proc = process) {
  if (typeof proc.send !== 'function') return
  proc.on('message', (message, socket) => {
    if (message?.type !== HANDOFF || !socket || typeof message.head !== 'string') return
    socket.once('close', () => {
      if (proc.connected) proc.send({ type: HANDOFF_CLOSED })
    })
    socket.unshift(Buffer.from(message.head, 'base64'))
    httpServer.emit('connection', socket)
  })
}
