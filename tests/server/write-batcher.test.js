/**
 * The turn writer (server/realtime/write-batcher.js): a connection's
 * messages of one turn of the event loop go out after it as one write, in
 * order; at most FLUSH_CHUNK connections are written per turn; a socket no
 * longer open gets nothing; a flush before a close puts the turn's
 * messages ahead of the close frame.
 */
import { once } from 'node:events'
import { describe, it, expect, afterEach } from 'vitest'
import WebSocket, { WebSocketServer } from 'ws'
import { socketWriter, TurnWriter, FLUSH_CHUNK } from '../../server/realtime/write-batcher.js'
import { OutgoingMessage, WEBSOCKET_OPTIONS } from '../../server/realtime/outgoing-message.js'

const nextTurn = () => new Promise((resolve) => setImmediate(resolve))

/** A stand-in for an open ws WebSocket that logs the writes its sender is handed. */
function fakeWebSocket (id, log) {
  const socket = Object.create(WebSocket.prototype, { readyState: { value: WebSocket.OPEN } })

  socket._socket = { write: (bytes) => log.push([id, bytes.length]) }
  return socket
}

describe('write batcher', () => {
  let server
  afterEach(async () => {
    for (const client of server?.clients ?? []) client.terminate()
    await new Promise((resolve) => server?.close(resolve) ?? resolve())
  })

  /** A real server socket and its client, the client's messages collected. */
  async function connected () {
    server = new WebSocketServer({ port: 0, host: '127.0.0.1', ...WEBSOCKET_OPTIONS })
    await once(server, 'listening')
    const client = new WebSocket(`ws://127.0.0.1:${server.address().port}`)
    const [socket] = await once(server, 'connection')
    await once(client, 'open')
    const received = []
    client.on('message', (data, isBinary) => received.push(isBinary ? [...data] : data.toString()))
    const arrived = (n) => new Promise((resolve) => { const poll = () => (received.length >= n ? resolve() : setTimeout(poll, 5)); poll() })
    return { socket, client, received, arrived }
  }

  it('writes every message of one turn after it, in order, as one write', async () => {
    const { socket, client, received, arrived } = await connected()
    const raw = socket._socket
    const writes = []
    const write = raw.write.bind(raw)
    raw.write = (chunk, ...rest) => { writes.push(chunk.length); return write(chunk, ...rest) }

    const out = socketWriter(socket)
    expect(out).toBeInstanceOf(TurnWriter)
    for (const message of ['a', 'b']) out.write(new OutgoingMessage(message))
    out.write(new OutgoingMessage(new Uint8Array([1, 2, 3])))
    await Promise.resolve()
    out.write(new OutgoingMessage('c')) // a microtask of the same turn joins the batch
    expect(writes).toEqual([])
    expect(out.queuedBytes).toBe(3 + 3 + 5 + 3)

    await nextTurn()
    expect(writes).toEqual([14]) // four framed messages, one write
    expect(out.queuedBytes).toBe(0)
    await arrived(4)
    expect(received).toEqual(['a', 'b', [1, 2, 3], 'c'])
    client.close()
  })

  it('writes what a turn queued before a close frame when flushed first, and nothing to a socket that closed', async () => {
    const { socket, client, received } = await connected()
    const out = socketWriter(socket)
    out.write(new OutgoingMessage('last words'))
    out.flush()
    socket.close(1000, 'bye')
    expect(out.write(new OutgoingMessage('too late'))).toBe(false)
    const [code] = await once(client, 'close')
    expect(code).toBe(1000)
    expect(received).toEqual(['last words'])

    // Queued while open, closed before its turn: dropped.
    const second = await connected()
    const out2 = socketWriter(second.socket)
    out2.write(new OutgoingMessage('never'))
    second.socket.close(1000, 'bye')
    await nextTurn()
    await once(second.client, 'close')
    expect(second.received).toEqual([])
  })

  it('writes at most FLUSH_CHUNK connections per turn, the rest in the next turns, in the order their first message came', async () => {
    const log = []
    const writers = Array.from({ length: 2 * FLUSH_CHUNK + 5 }, (_, id) => new TurnWriter(fakeWebSocket(id, log)))
    const message = new OutgoingMessage('x')
    for (const writer of writers) writer.write(message)
    writers[0].write(message) // already waiting: joins its queue, not listed twice

    await nextTurn()
    expect(log.map(([id]) => id)).toEqual(writers.slice(0, FLUSH_CHUNK).map((_, id) => id))
    expect(log[0][1]).toBe(2 * message.wire.length) // its two messages in one write
    // A writer still waiting for its chunk keeps its place; one already written is listed again, behind the others.
    writers[FLUSH_CHUNK + 1].write(message)
    writers[0].write(message)
    await nextTurn()
    expect(log.length).toBe(2 * FLUSH_CHUNK)
    await nextTurn()
    expect(log.map(([id]) => id)).toEqual([...writers.map((_, id) => id), 0])

    // Drained: the next message is written at the end of its own turn.
    writers[7].write(message)
    await nextTurn()
    expect(log.at(-1)[0]).toBe(7)
  })

  it('leaves no cleared idle timer on the socket to refresh on every read and write', async () => {
    const { socket, client } = await connected()
    const raw = socket._socket
    // As an HTTP server leaves an upgraded socket: a timeout set, then cleared by ws (setTimeout(0)).
    raw.setTimeout(30_000)
    raw.setTimeout(0)
    const timer = () => Object.getOwnPropertySymbols(raw).filter((key) => key.description === 'timeout').map((key) => raw[key])
    expect(timer().some((t) => t !== null && t !== undefined)).toBe(true)
    socketWriter(socket)
    expect(timer().every((t) => t === null || t === undefined)).toBe(true)
    // A timeout set afterwards still works.
    const timedOut = new Promise((resolve) => raw.once('timeout', resolve))
    raw.setTimeout(20)
    await timedOut
    raw.setTimeout(0)
    client.close()
  })

  it('hands anything that is not a ws socket each payload at once', () => {
    const sent = []
    const out = socketWriter({ send: (payload, options) => sent.push([payload, options.binary]) })
    const bytes = new Uint8Array([3, 1])
    expect(out.write(new OutgoingMessage(bytes))).toBe(true)
    expect(out.write(new OutgoingMessage('{"type":"pong"}'))).toBe(true)
    expect(out.queuedBytes).toBe(0)
    expect(sent).toEqual([[bytes, true], ['{"type":"pong"}', false]])
  })
})
