import { once } from 'node:events'
import { describe, it, expect, afterEach } from 'vitest'
import WebSocket, { WebSocketServer } from 'ws'
import { holdWritesUntilEndOfTurn, FLUSH_CHUNK } from '../../server/realtime/write-batcher.js'

/** A stand-in for a ws WebSocket whose TCP socket logs its uncork. */
function fakeWebSocket (id, log) {
  const raw = { writableCorked: 0, destroyed: false, cork () { this.writableCorked++ }, uncork () { this.writableCorked--; log.push(id) } }
  return { _socket: raw }
}

const nextTurn = () => new Promise((resolve) => setImmediate(resolve))

describe('write batcher', () => {
  let server
  afterEach(async () => {
    for (const client of server?.clients ?? []) client.terminate()
    await new Promise((resolve) => server?.close(resolve) ?? resolve())
  })

  it('sends every frame of one turn in one write, in order, and uncorks after the turn', async () => {
    server = new WebSocketServer({ port: 0, host: '127.0.0.1' })
    await once(server, 'listening')
    const client = new WebSocket(`ws://127.0.0.1:${server.address().port}`)
    const [socket] = await once(server, 'connection')
    await once(client, 'open')
    const received = []
    client.on('message', (data, isBinary) => received.push(isBinary ? [...data] : data.toString()))

    const raw = socket._socket
    const writes = []
    const writev = raw._writev.bind(raw)
    raw._writev = (chunks, callback) => { writes.push(chunks.length); writev(chunks, callback) }

    for (const message of ['a', 'b']) {
      holdWritesUntilEndOfTurn(socket)
      socket.send(message)
    }
    holdWritesUntilEndOfTurn(socket)
    socket.send(Buffer.from([1, 2, 3]), { binary: true })
    await Promise.resolve()
    holdWritesUntilEndOfTurn(socket) // a microtask of the same turn joins the batch
    socket.send('c')
    expect(raw.writableCorked).toBe(1)

    await new Promise((resolve) => setImmediate(resolve))
    expect(raw.writableCorked).toBe(0)
    expect(writes).toEqual([8]) // four frames, header and payload each, in one writev
    await new Promise((resolve) => { const poll = () => (received.length === 4 ? resolve() : setTimeout(poll, 5)); poll() })
    expect(received).toEqual(['a', 'b', [1, 2, 3], 'c'])
    client.close()
  })

  it('writes at most FLUSH_CHUNK sockets per turn, the rest in the next turns, oldest first', async () => {
    const log = []
    const sockets = Array.from({ length: 2 * FLUSH_CHUNK + 5 }, (_, id) => fakeWebSocket(id, log))
    for (const socket of sockets) holdWritesUntilEndOfTurn(socket)
    holdWritesUntilEndOfTurn(sockets[0]) // already corked: not listed twice
    expect(sockets.every((socket) => socket._socket.writableCorked === 1)).toBe(true)

    await nextTurn()
    expect(log).toEqual(sockets.slice(0, FLUSH_CHUNK).map((_, id) => id))
    // A socket still waiting for its chunk is not corked again; one already written is, behind the others.
    holdWritesUntilEndOfTurn(sockets[FLUSH_CHUNK + 1])
    holdWritesUntilEndOfTurn(sockets[0])
    await nextTurn()
    expect(log.length).toBe(2 * FLUSH_CHUNK)
    await nextTurn()
    expect(log).toEqual([...sockets.map((_, id) => id), 0])
    expect(sockets.every((socket) => socket._socket.writableCorked === 0)).toBe(true)

    // Drained: the next cork is written at the end of its own turn.
    holdWritesUntilEndOfTurn(sockets[7])
    await nextTurn()
    expect(log.at(-1)).toBe(7)
  })

  it('leaves a closed socket alone', () => {
    expect(() => holdWritesUntilEndOfTurn({ _socket: null })).not.toThrow()
  })
})
