/**
 * A child process for tests/cluster/socket-handoff.test.js: an HTTP server
 * with a WebSocket server that takes handed-over sockets
 * (server/cluster/socket-handoff.js) and tells each client what it sees of
 * its connection: the peer's port and the forwarded-for header.
 */
import http from 'node:http'
import { WebSocketServer } from 'ws'
import { acceptHandedOffSockets } from '../../../server/cluster/socket-handoff.js'

const server = http.createServer((request, response) => response.end('http'))
const sockets = new WebSocketServer({ server })
sockets.on('connection', (socket, request) => {
  socket.send(JSON.stringify({ pid: process.pid, remotePort: request.socket.remotePort, forwardedFor: request.headers['x-forwarded-for'], url: request.url }))
  socket.on('message', (data) => socket.send(String(data)))
})
acceptHandedOffSockets(server)
server.listen(0, '127.0.0.1', () => process.send({ type: 'listening', port: server.address().port }))
