import { describe, it, expect } from 'vitest'
import { EventEmitter } from 'node:events'
import { Connection, createMessageParser } from '../../server/realtime/connection.js'
import { createMetrics } from '../../server/metrics.js'
import { TokenBucket } from '../../server/limits/token-bucket.js'
import { seedsDelivery } from '../../server/realtime/delivery-seeds.js'
import { emptyTally } from '../../server/realtime/deliveries.js'
import { decodeDropEvents } from '../../protocol/drop-events-codec.js'
import { OutgoingMessage } from '../../server/realtime/outgoing-message.js'

/** A stand-in for a ws WebSocket whose send queue the test controls. */
function fakeSocket () {
  const socket = new EventEmitter()
  socket.bufferedAmount = 0
  socket.sent = []
  socket.closedWith = null
  socket.send = (data) => socket.sent.push(data)
  socket.close = (code, reason) => { socket.closedWith = { code, reason } }
  socket.ping = () => {}
  socket.terminate = () => { socket.closedWith = { code: 'terminated' } }
  // ws: stop reading the peer (a socket dropped for abuse is not read any more).
  socket.paused = false
  socket.pause = () => { socket.paused = true }
  return socket
}

function setup () {
  const socket = fakeSocket()
  const metrics = createMetrics({ defaultMetrics: false })
  const released = []
  const arena = {
    config: { minBet: 1, maxBet: 100 },
    connected () {},
    disconnected () {},
    accounts: { release: (account) => released.push(account) },
    join: () => ({ type: 'joined' }),
    leave: () => 'r'
  }
  const connection = new Connection({ socket, arena, parseMessage: createMessageParser({ minBet: 1, maxBet: 100 }), metrics, log: { warn () {}, error () {} }, softLimit: 1000, hardLimit: 5000, messageLimiter: new TokenBucket({ rate: 1000, burst: 1000 }) })
  const account = { playerId: 'p', balance: 10, clientSeed: 'c', seed: { hash: 'h', nextNonce: 0 }, connections: new Set() }
  return { socket, metrics, connection, account, released }
}

const value = async (metrics, name) => (await metrics.registry.getSingleMetric(name).get()).values[0]?.value ?? 0

describe('Connection backpressure', () => {
  it('skips snapshots over the soft limit but still sends events', async () => {
    const { socket, metrics, connection, account } = setup()
    connection.authenticated(account)
    const frame = Buffer.from([1, 0, 0, 0, 0, 0, 0])
    connection.sendRoomFrame(new OutgoingMessage(frame), null)
    expect(socket.sent.at(-1)).toBe(frame)
    socket.bufferedAmount = 1001
    const sent = socket.sent.length
    connection.sendRoomFrame(new OutgoingMessage(frame), null)
    connection.sendRoomFrame(new OutgoingMessage(frame), null)
    expect(socket.sent.length).toBe(sent)
    expect(await value(metrics, 'plinko_snapshots_skipped_total')).toBe(2)
    connection.sendEvent('{"type":"settled"}', 'settled')
    expect(socket.sent.at(-1)).toBe('{"type":"settled"}')
    expect(socket.closedWith).toBeNull()
  })

  it('closes a client over the hard limit with 1013 E_SLOW_CONSUMER and sends it nothing more', async () => {
    const { socket, metrics, connection, account, released } = setup()
    connection.authenticated(account)
    socket.bufferedAmount = 5001
    connection.sendRoomFrame(new OutgoingMessage(Buffer.from([1])), null)
    expect(socket.closedWith).toEqual({ code: 1013, reason: 'E_SLOW_CONSUMER' })
    expect(socket.paused).toBe(true) // not read any more
    expect(await value(metrics, 'plinko_ws_slow_consumers_closed_total')).toBe(1)
    expect(released).toEqual([account])
    const sent = socket.sent.length
    socket.bufferedAmount = 0
    connection.sendEvent('{}', 'x')
    expect(socket.sent.length).toBe(sent)

    const other = setup()
    other.connection.authenticated(other.account)
    other.socket.bufferedAmount = 5001
    other.connection.sendEvent('{"type":"dropped"}', 'dropped')
    expect(other.socket.closedWith.code).toBe(1013)

    // A drop-events frame (seeds delivery) is an event: never skipped over the soft limit, closed over the hard one.
    const seeds = setup()
    seeds.connection.authenticated(seeds.account)
    const frame = new Uint8Array([3, 0, 0, 0, 0])
    seeds.socket.bufferedAmount = 4999
    expect(seeds.connection.sendEventFrame(new OutgoingMessage(frame))).toBe(true)
    expect(seeds.socket.sent.at(-1)).toBe(frame)
    seeds.socket.bufferedAmount = 5001
    expect(seeds.connection.sendEventFrame(new OutgoingMessage(frame))).toBe(false)
    expect(seeds.socket.closedWith.code).toBe(1013)
  })

  it('handles messages that arrived before authentication, in order, and refuses a flood of them', () => {
    const { socket, connection, account } = setup()
    socket.emit('message', Buffer.from('{"type":"ping","ref":1}'), false)
    socket.emit('message', Buffer.from('{"type":"ping","ref":2}'), false)
    expect(socket.sent).toEqual([])
    connection.authenticated(account)
    const replies = socket.sent.map((text) => JSON.parse(text))
    expect(replies.map((m) => [m.type, m.ref])).toEqual([['welcome', undefined], ['pong', 1], ['pong', 2]])

    const flooded = setup()
    for (let i = 0; i < 40; i++) flooded.socket.emit('message', Buffer.from('{"type":"ping"}'), false)
    expect(flooded.socket.closedWith.code).toBe(1008)
    expect(flooded.socket.paused).toBe(true)
  })

  it('terminates a peer that missed a heartbeat', () => {
    const { socket, connection, account } = setup()
    connection.authenticated(account)
    connection.heartbeat()
    expect(socket.closedWith).toBeNull()
    socket.emit('pong')
    connection.heartbeat()
    expect(socket.closedWith).toBeNull()
    connection.heartbeat()
    expect(socket.closedWith).toEqual({ code: 'terminated' })
  })
})

describe("the seeds delivery's owner section", () => {
  /** A signed-in connection in a seeds feed of a room with no balls, at an event tick, nothing sent yet. */
  function seedsRoom () {
    const { socket, connection, account } = setup()
    connection.authenticated(account)
    const room = {
      id: '8-low', tick: 15, snapshotPhase: 0, eventEvery: 15, checkEvery: 120, visibleCount: 0, visible: new Uint8Array(0),
      simulator: { world: { bodyCount: 0 } },
      awaitsCommitBefore: () => false // no drop being committed
    }
    const feed = seedsDelivery.createFeed(room)
    feed.clients.add(connection)
    connection.room = room
    connection.feed = feed
    socket.sent.length = 0
    return { socket, connection, room, feed }
  }

  it("holds the owner's settled for the room's next frame, and sends held messages first when anything else goes out", () => {
    const { socket, connection, room, feed } = seedsRoom()
    const settledA = '{"type":"settled","dropId":1,"balance":12}'
    connection.sendSettled(settledA, room)
    expect(socket.sent).toEqual([]) // held
    feed.afterTick(emptyTally())
    // One frame, for the owner only (nothing else happened in the room): no events, its settled in the owner's section.
    expect(socket.sent).toHaveLength(1)
    expect(decodeDropEvents(socket.sent[0])).toMatchObject({ tick: 15, events: [], own: [JSON.parse(settledA)] })

    // Held, then a `dropped` is sent before the next frame: the settled goes first, on its own, and the frame carries nothing.
    socket.sent.length = 0
    const settledB = '{"type":"settled","dropId":2,"balance":20}'
    connection.sendSettled(settledB, room)
    connection.sendEvent('{"type":"dropped","dropId":3,"balance":19}', 'dropped')
    expect(socket.sent).toEqual([settledB, '{"type":"dropped","dropId":3,"balance":19}'])
    room.tick = 30
    feed.afterTick(emptyTally())
    expect(socket.sent).toHaveLength(2)

    // Leaving the room (or closing) sends what is held.
    const settledC = '{"type":"settled","dropId":4,"ref":"é"}'
    connection.sendSettled(settledC, room)
    feed.leave(connection)
    expect(socket.sent.at(-1)).toBe(settledC)
    const settledD = '{"type":"settled","dropId":5}'
    feed.clients.add(connection)
    connection.sendSettled(settledD, room)
    connection.close(1001, 'bye')
    expect(socket.sent.at(-1)).toBe(settledD)
  })

  it('writes the owner section in ASCII whatever the text, and a settled from another room goes at once', () => {
    const { socket, connection, room, feed } = seedsRoom()
    const text = '{"type":"settled","dropId":1,"ref":"ü→😀"}'
    connection.sendSettled(text, room)
    feed.afterTick(emptyTally())
    const frame = socket.sent[0]
    expect([...frame.subarray(15)].every((byte) => byte < 0x80)).toBe(true)
    expect(decodeDropEvents(frame).own).toEqual([JSON.parse(text)])
    connection.sendSettled('{"type":"settled","dropId":9}', { id: 'another' })
    expect(socket.sent.at(-1)).toBe('{"type":"settled","dropId":9}')
  })
})
