import { describe, it, expect } from 'vitest'
import Ajv from 'ajv'
import { useServerOn, eventually } from '../server/helpers/server.js'
import { GameClient } from '../server/helpers/game-client.js'
import { splitRoomFrame } from '../../protocol/snapshot-codec.js'
import { decodeDropEvents, DROP_EVENTS_KIND } from '../../protocol/drop-events-codec.js'

/**
 * What a real session receives, checked against the published AsyncAPI
 * document (/api/asyncapi.json): every JSON text frame and every event in a
 * binary room frame matches its message's schema (which refuses unknown
 * fields), so a field added to, renamed in or dropped from a server message
 * without the document fails here. Both ways of hearing of other players'
 * drops are played: room frames (SPECTATOR_EVENTS=snapshot) and `events`
 * messages (immediate).
 */
describe.each(['snapshot', 'immediate'])('WebSocket messages against the AsyncAPI document (SPECTATOR_EVENTS=%s)', (mode) => {
  const context = useServerOn('sqlite', { env: { SPECTATOR_EVENTS: mode } })

  /** A client whose every frame is kept as it came: JSON text frames, and the events of binary room frames. */
  async function rawClient (token) {
    const client = new GameClient(context.server.wsUrl(token))
    client.raw = []
    client.dropEvents = []
    client.socket.on('message', (data, isBinary) => {
      if (!isBinary) client.raw.push(JSON.parse(data.toString()))
      else if (data[0] === DROP_EVENTS_KIND) client.dropEvents.push(decodeDropEvents(data))
      else for (const event of splitRoomFrame(data).events) client.raw.push({ ...event, via: 'room frame' })
    })
    await client.opened
    client.welcome = await client.take('welcome')
    return client
  }

  it('every message a session receives matches its documented schema', async () => {
    const { server } = context
    const document = (await server.api('GET', '/api/asyncapi.json')).body
    const messages = document.channels.game.messages
    const ajv = new Ajv({ strict: false, allErrors: true })
    const validators = Object.fromEntries(Object.entries(messages).filter(([, m]) => m.contentType === 'application/json').map(([name, m]) => [name, ajv.compile(m.payload)]))

    const owner = await server.session()
    const watcher = await server.session()
    const player = await rawClient(owner.token)
    const spectator = await rawClient(watcher.token)
    const seedsWatcher = await rawClient((await server.session()).token)

    spectator.send({ type: 'join', room: '8-low', ref: 'watch' })
    await spectator.take('joined')
    seedsWatcher.send({ type: 'join', room: '8-low', delivery: 'seeds' })
    expect(await seedsWatcher.take('joined')).toMatchObject({ delivery: 'seeds', eventEvery: 15 })
    player.send({ type: 'join', room: '8-low', ref: 1 })
    await player.take('joined')
    player.send({ type: 'drop', bet: 10, ref: 'd1' })
    player.send({ type: 'drop', bet: 20, clientSeed: 'docs-test' })
    const dropped = await player.take('dropped')
    await player.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    await spectator.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    // The seeds socket hears of the drops in drop-events frames (binary, described as dropEvents), never as JSON.
    await eventually(() => seedsWatcher.dropEvents.some((frame) => frame.events.some((e) => e.dropId === dropped.dropId)))
    expect(seedsWatcher.raw.filter((m) => m.type === 'dropped' || m.type === 'settled')).toEqual([])
    expect(messages.dropEvents.contentType).toBe('application/octet-stream')
    player.send({ type: 'ping', ref: 'p' })
    await player.take('pong')
    await player.expectError({ type: 'drop', bet: 10, extra: 1 })
    await player.expectError({ type: 'teleport' })
    player.send({ type: 'leave' })
    await player.take('left')

    // A bad token's error, as a client that gets no welcome sees it.
    const rejected = new GameClient(server.wsUrl('0'.repeat(64)))
    const rejectedFrames = []
    rejected.socket.on('message', (data) => rejectedFrames.push(JSON.parse(data.toString())))
    expect((await rejected.closed).code).toBe(4401)

    const received = [...player.raw, ...spectator.raw, ...seedsWatcher.raw, ...rejectedFrames]
    const types = new Set(received.map((m) => m.type))
    for (const type of ['welcome', 'joined', 'dropped', 'settled', 'pong', 'left', 'error']) expect(types, type).toContain(type)
    if (mode === 'immediate') expect(types).toContain('events')
    else expect(received.some((m) => m.via === 'room frame')).toBe(true)
    for (const { via, ...message } of received) {
      const validate = validators[message.type]
      expect(validate, `a ${message.type} message is documented`).toBeDefined()
      expect(validate(message), `${message.type}${via ? ` (${via})` : ''}: ${ajv.errorsText(validate.errors)}\n${JSON.stringify(message).slice(0, 300)}`).toBe(true)
    }
    // The schemas do refuse what is not documented.
    expect(validators.settled({ ...received.find((m) => m.type === 'settled'), surprise: true })).toBe(false)
    await player.close()
    await spectator.close()
    await seedsWatcher.close()
  })
})
