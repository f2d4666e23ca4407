import { describe, it, expect } from 'vitest'
import Ajv from 'ajv'
import { useServerOn, eventually } from '../server/helpers/server.js'
import { GameClient } from '../server/helpers/game-client.js'
import { splitRoomFrame, ROOM_FRAME_KIND } from '../../protocol/snapshot-codec.js'
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

  /**
   * The same, driven by the document alone: every client message it lists
   * (its operations with action `receive`) is sent as each of its examples
   * and with each value of each optional field of a closed set (enum, const,
   * boolean), so a field or a message added to the document is played as
   * soon as it is documented. Each must be answered by one of the replies the
   * document names for it, not an error; the same message with an unknown
   * field must be refused. Every frame received meanwhile must be documented:
   * a JSON text frame matches the schema of its `type`, a binary frame's
   * first byte is the `x-frame-kind` of a documented binary message (and a
   * room frame's events match their schemas).
   */
  it('answers every documented client message as documented, and sends only documented messages', async () => {
    const { server } = context
    const document = (await server.api('GET', '/api/asyncapi.json')).body
    const messages = document.channels.game.messages
    const nameOf = ({ $ref }) => $ref.split('/').pop()
    const ajv = new Ajv({ strict: false, allErrors: true })
    const validators = Object.fromEntries(Object.entries(messages).filter(([, m]) => m.contentType === 'application/json').map(([name, m]) => [name, ajv.compile(m.payload)]))
    const binaryKinds = new Map(Object.values(messages).filter((m) => m.contentType === 'application/octet-stream').map((m) => [m['x-frame-kind'], m.name]))
    expect(binaryKinds.size, 'every binary message names its frame kind').toBe(Object.values(messages).filter((m) => m.contentType === 'application/octet-stream').length)

    const session = await server.session()
    const client = new GameClient(context.server.wsUrl(session.token))
    /** Every frame as it came: [what it is, the message or the events] */
    const frames = []
    client.socket.on('message', (data, isBinary) => {
      if (!isBinary) return frames.push(JSON.parse(data.toString()))
      const kind = binaryKinds.get(data[0])
      frames.push({ binary: kind ?? `undocumented kind ${data[0]}` })
      if (data[0] === ROOM_FRAME_KIND) for (const event of splitRoomFrame(data).events) frames.push({ ...event, via: 'room frame' })
    })
    await client.opened
    await client.take('welcome')

    let refs = 0
    /** Sends `message` with a fresh ref; resolves with the reply that echoes it. */
    const roundTrip = async (message) => {
      const ref = `doc-${++refs}`
      client.send({ ...message, ref })
      return client.take((m) => m.ref === ref)
    }
    const clientOperations = Object.values(document.operations).filter((op) => op.action === 'receive')
    expect(clientOperations.length).toBeGreaterThanOrEqual(4)
    // The one state rule of the protocol: a room is joined before anything else is played in it.
    const enter = messages.join.examples[0].payload
    let sent = 0
    for (const operation of clientOperations) {
      const name = nameOf(operation.messages[0])
      const replies = (operation.reply?.messages ?? []).map(nameOf)
      expect(replies.length, `${name} has documented replies`).toBeGreaterThan(0)
      for (const variant of variantsOf(messages[name])) {
        const where = `${name} ${JSON.stringify(variant)}`
        expect(validators[name](variant), `${where}: ${ajv.errorsText(validators[name].errors)}`).toBe(true)
        if (name !== 'join') expect((await roundTrip(enter)).type).toBe('joined')
        const reply = await roundTrip(variant)
        expect(replies, where).toContain(reply.type)
        expect(reply.type, `${where} → ${JSON.stringify(reply)}`).not.toBe('error')
        const refused = await roundTrip({ ...variant, surprise: true })
        expect(refused, where).toMatchObject({ type: 'error', code: 'E_BAD_MESSAGE' })
        sent++
      }
    }
    // The drops land: their settled events are checked too.
    const drops = frames.filter((m) => m.type === 'dropped' && m.player === session.playerId && !m.via)
    expect(drops.length).toBeGreaterThan(0)
    for (const drop of drops) await client.take((m) => m.type === 'settled' && m.dropId === drop.dropId)
    await client.close()

    expect(sent).toBeGreaterThanOrEqual(6)
    for (const { via, binary, ...message } of frames) {
      if (binary) {
        expect(binary, 'a binary frame of a documented kind').not.toMatch(/^undocumented/)
        continue
      }
      const validate = validators[message.type]
      expect(validate, `a ${message.type} message is documented`).toBeDefined()
      expect(validate(message), `${message.type}${via ? ` (${via})` : ''}: ${ajv.errorsText(validate.errors)}\n${JSON.stringify(message).slice(0, 300)}`).toBe(true)
    }
  })
})

/**
 * The client messages worth sending for one documented message: each of its
 * examples, then the first with each value of each optional field that has
 * a closed set of values. An optional field with an open set must be shown
 * in an example (or the document is not enough to play it).
 * @param {{ name: string, payload: any, examples?: { payload: object }[] }} message
 */
function variantsOf (message) {
  const examples = (message.examples ?? []).map((example) => example.payload)
  expect(examples.length, `${message.name} has examples in the document`).toBeGreaterThan(0)
  const variants = [...examples]
  const required = new Set(message.payload.required ?? [])
  for (const [field, schema] of Object.entries(message.payload.properties ?? {})) {
    if (required.has(field) || field === 'ref') continue
    const values = schema.const !== undefined ? [schema.const] : schema.enum ?? (schema.type === 'boolean' ? [false, true] : null)
    if (values) for (const value of values) variants.push({ ...examples[0], [field]: value })
    else expect(examples.some((example) => field in example), `${message.name}.${field}: an example shows it, or its values are a closed set`).toBe(true)
  }
  return variants
}
