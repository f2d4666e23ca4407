/**
 * A message framed once for the wire (server/realtime/outgoing-message.js)
 * reaches a real ws client as the same message, text or binary, at every
 * length class of RFC 6455 (7-bit, 16-bit and 64-bit lengths), and the same
 * framed bytes go to several sockets in order with what ws itself sends.
 */
import { describe, it, expect, afterEach } from 'vitest'
import { WebSocketServer, WebSocket } from 'ws'
import { OutgoingMessage, socketWriter, WEBSOCKET_OPTIONS } from '../../server/realtime/outgoing-message.js'

let server
afterEach(() => new Promise((resolve) => server ? server.close(resolve) : resolve()))

/** A server and `count` clients, each client's messages collected as [isBinary, payload]. */
async function connected (count) {
  server = new WebSocketServer({ host: '127.0.0.1', port: 0, ...WEBSOCKET_OPTIONS })
  await new Promise((resolve) => server.once('listening', resolve))
  const serverSockets = []
  server.on('connection', (socket) => serverSockets.push(socket))
  const clients = []
  for (let i = 0; i < count; i++) {
    const client = new WebSocket(`ws://127.0.0.1:${server.address().port}`)
    client.received = []
    client.on('message', (data, isBinary) => client.received.push([isBinary, isBinary ? Uint8Array.from(data) : data.toString()]))
    await new Promise((resolve) => client.once('open', resolve))
    clients.push(client)
  }
  while (serverSockets.length < count) await new Promise((resolve) => server.once('connection', resolve))
  return { serverSockets, clients }
}

const arrived = (client, n) => new Promise((resolve) => {
  const check = () => client.received.length >= n ? resolve() : client.once('message', () => setImmediate(check))
  check()
})

describe('messages framed once for the wire', () => {
  it('arrive whole at every length class, text and binary, to every socket, in order with ws.send', async () => {
    const { serverSockets, clients } = await connected(2)
    const lengths = [0, 1, 125, 126, 65535, 65536, 70000]
    const messages = []
    for (const length of lengths) {
      const bytes = Uint8Array.from({ length }, (_, i) => (i * 7 + length) & 0xff)
      messages.push(new OutgoingMessage(bytes), new OutgoingMessage('é'.repeat(length >> 1) + 'x'.repeat(length & 1)))
    }
    const writers = serverSockets.map(socketWriter)
    for (const message of messages) for (const write of writers) expect(write(message)).toBe(true)
    // ws's own send, after them, keeps its place.
    for (const socket of serverSockets) socket.send('last')
    for (const client of clients) {
      await arrived(client, messages.length + 1)
      expect(client.received).toEqual([...messages.map((m) => [m.binary, m.payload]), [false, 'last']])
    }
    // The same bytes for every socket: framed once.
    expect(messages[3].wire).toBe(messages[3].wire)
    for (const client of clients) client.close()
  })

  it('leaves no cleared idle timer on the socket to refresh on every write', async () => {
    const { serverSockets, clients } = await connected(1)
    const raw = serverSockets[0]._socket
    // As an HTTP server leaves an upgraded socket: a timeout set, then cleared by ws (setTimeout(0)).
    raw.setTimeout(30_000)
    raw.setTimeout(0)
    const timer = () => Object.getOwnPropertySymbols(raw).filter((key) => key.description === 'timeout').map((key) => raw[key])
    expect(timer().some((t) => t !== null && t !== undefined)).toBe(true)
    socketWriter(serverSockets[0])
    expect(timer().every((t) => t === null || t === undefined)).toBe(true)
    // A timeout set afterwards still works.
    const timedOut = new Promise((resolve) => raw.once('timeout', resolve))
    raw.setTimeout(20)
    await timedOut
    raw.setTimeout(0)
    clients[0].close()
  })

  it('writes nothing to a socket that is closing', async () => {
    const { serverSockets, clients } = await connected(1)
    const write = socketWriter(serverSockets[0])
    serverSockets[0].close(1000, 'bye')
    expect(write(new OutgoingMessage('too late'))).toBe(false)
    await new Promise((resolve) => clients[0].once('close', resolve))
    expect(clients[0].received).toEqual([])
  })

  it('hands anything that is not a ws socket the payload', () => {
    const sent = []
    const write = socketWriter({ send: (payload, options) => sent.push([payload, options.binary]) })
    const bytes = new Uint8Array([3, 1])
    expect(write(new OutgoingMessage(bytes))).toBe(true)
    expect(write(new OutgoingMessage('{"type":"pong"}'))).toBe(true)
    expect(sent).toEqual([[bytes, true], ['{"type":"pong"}', false]])
  })
})
