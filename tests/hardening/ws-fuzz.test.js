import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import fc from 'fast-check'
import WebSocket from 'ws'
import { ERROR_CODES } from '../../server/errors.js'
import { createMessageParser } from '../../server/realtime/connection.js'
import { ROOM_IDS } from '../../protocol/room-id.js'
import { STORE_KINDS, storeBackend } from '../server/helpers/stores.js'
import { startServer } from '../server/helpers/server.js'
import { GameClient } from '../server/helpers/game-client.js'
import { ledgerTotals, expectConsistentLedger } from './helpers/ledger.js'

/**
 * Fuzzes the game protocol over real WebSockets with a seeded generator
 * (fast-check): every frame gets exactly one reply — a named error or the
 * normal answer to a valid message — or a close with a proper close code;
 * refused messages change no balance and write no ledger row; the process
 * keeps serving players afterwards.
 */
const SEED = Number(process.env.PLINKO_FUZZ_SEED ?? 20261123)
const CONNECTIONS = 10
const MESSAGES_PER_CONNECTION = 1000
const REPLY_TYPES = new Set(['error', 'pong', 'joined', 'left'])

const weirdNumber = fc.oneof(
  fc.constantFrom('NaN', 'Infinity', '-Infinity', '1e400', '-1e400', '1e-400', '-0', '0', '-1', '1.5', '0.0001', '9007199254740993', '1e21', '0x10', '1_000', '"10"', 'null', 'true', '[]', '{}', '[10]'),
  fc.double().map((x) => JSON.stringify(x) ?? 'null'),
  fc.integer({ min: -1e15, max: 1e15 }).map(String),
  fc.bigInt({ min: -(10n ** 30n), max: 10n ** 30n }).map(String)
)
const nastyString = fc.oneof(
  fc.string({ maxLength: 80 }),
  fc.string({ unit: 'binary', maxLength: 70 }),
  fc.string({ unit: fc.integer({ min: 0, max: 31 }).map((c) => String.fromCharCode(c)), minLength: 1, maxLength: 10 }),
  fc.constantFrom('', ' ', '\u0000', 'seed\u0007', '\u202e', '\ud800', '\udfff', 'é', '😀', '<script>', '../../etc/passwd', '__proto__', 'x'.repeat(65), 'x'.repeat(64))
)
const anyJson = fc.jsonValue({ maxDepth: 3 })
const roomId = fc.oneof(fc.constantFrom(...ROOM_IDS), fc.constantFrom('7-low', '17-high', '8-extreme', '8-LOW', ' 8-low', '8-low ', 'lobby', ''), nastyString)
const type = fc.oneof(fc.constantFrom('join', 'leave', 'drop', 'ping'), fc.constantFrom('JOIN', 'Drop', 'teleport', '', '__proto__', 'constructor', 'toString'), fc.string({ maxLength: 20 }))

/** A JSON object as text with raw (possibly non-JSON) values spliced in. */
const messageObject = fc.record({
  type: fc.oneof({ weight: 6, arbitrary: type.map((t) => JSON.stringify(t)) }, { weight: 1, arbitrary: weirdNumber }),
  fields: fc.dictionary(
    fc.oneof(fc.constantFrom('bet', 'clientSeed', 'room', 'ref', 'extra', '__proto__', 'constructor', 'type'), fc.string({ maxLength: 10 })),
    fc.oneof(weirdNumber, nastyString.map((s) => JSON.stringify(s)), roomId.map((s) => JSON.stringify(s)), anyJson.map((v) => JSON.stringify(v))),
    { maxKeys: 5 }
  ),
  typeFirst: fc.boolean()
}).map(({ type, fields, typeFirst }) => {
  const parts = Object.entries(fields).map(([k, v]) => `${JSON.stringify(k)}:${v}`)
  if (typeFirst) parts.unshift(`"type":${type}`)
  else parts.push(`"type":${type}`)
  return `{${parts.join(',')}}`
})

const frame = fc.oneof(
  { weight: 10, arbitrary: messageObject.map((text) => ({ text })) },
  { weight: 2, arbitrary: anyJson.map((v) => ({ text: JSON.stringify(v) })) },
  { weight: 2, arbitrary: messageObject.chain((text) => fc.nat({ max: Math.max(0, text.length - 1) }).map((cut) => ({ text: text.slice(0, cut) }))) },
  { weight: 1, arbitrary: fc.string({ maxLength: 200 }).map((text) => ({ text })) },
  { weight: 1, arbitrary: fc.integer({ min: 1, max: 1500 }).map((n) => ({ text: '['.repeat(n) + ']'.repeat(n) })) },
  { weight: 1, arbitrary: fc.uint8Array({ maxLength: 300 }).map((bytes) => ({ binary: Buffer.from(bytes) })) },
  { weight: 2, arbitrary: fc.record({ room: roomId }).map(({ room }) => ({ text: JSON.stringify({ type: 'join', room }) })) },
  { weight: 3, arbitrary: fc.record({ bet: fc.oneof(fc.integer(), fc.double()), clientSeed: fc.option(nastyString, { nil: undefined }) }).map((m) => ({ text: JSON.stringify({ type: 'drop', ...m }) })) }
)

describe.each(STORE_KINDS)('WebSocket protocol fuzz on %s', (kind) => {
  const backend = storeBackend(kind)
  let server
  let database
  let parse

  beforeAll(async () => {
    await backend.setup()
    database = await backend.newDatabase()
    server = await startServer(database, { env: { DROP_RATE: '10000', DROP_BURST: '10000', WS_MESSAGE_RATE: '100000', WS_MESSAGE_BURST: '100000' } })
    parse = createMessageParser(server.config)
  })

  afterAll(async () => {
    await server?.close()
    await backend.teardown()
  })

  /** Turns a generated frame that happens to be a valid, affordable drop into a refused one (bet over MAX_BET). */
  function refusedOnly (item) {
    if (item.binary) return item
    let message
    try { message = parse(item.text) } catch { return item }
    if (message.type !== 'drop') return item
    return { text: JSON.stringify({ ...message, bet: server.config.maxBet + 1 }) }
  }

  it(`answers ${CONNECTIONS * MESSAGES_PER_CONNECTION} malformed frames with one named reply each and changes nothing`, async () => {
    const players = []
    for (let i = 0; i < CONNECTIONS; i++) players.push(await server.player(i % 2 === 0 ? ROOM_IDS[i] : undefined))
    const before = await ledgerTotals(backend, database.database)
    const balances = await Promise.all(players.map((p) => server.api('GET', '/api/me', { token: p.token })))

    const frames = fc.sample(frame, { seed: SEED, numRuns: CONNECTIONS * MESSAGES_PER_CONNECTION }).map(refusedOnly)
    const codes = new Map()
    await Promise.all(players.map(async ({ client }, index) => {
      const mine = frames.slice(index * MESSAGES_PER_CONNECTION, (index + 1) * MESSAGES_PER_CONNECTION)
      const start = client.messages.length
      for (const item of mine) {
        if (item.binary) client.socket.send(item.binary, { binary: true })
        else client.socket.send(item.text)
      }
      await client.sync()
      // One reply per frame, plus the pong of sync(); nothing else (no drop was accepted).
      const replies = client.messages.slice(start, -1)
      expect(replies.length).toBe(mine.length)
      for (const reply of replies) {
        expect(REPLY_TYPES.has(reply.type), JSON.stringify(reply)).toBe(true)
        if (reply.type === 'error') {
          expect(ERROR_CODES[reply.code], reply.code).toBeDefined()
          expect(reply.code).not.toBe('E_INTERNAL')
          codes.set(reply.code, (codes.get(reply.code) ?? 0) + 1)
        }
      }
      expect(client.closeEvent).toBeNull()
    }))
    expect([...codes.keys()]).toEqual(expect.arrayContaining(['E_BAD_MESSAGE', 'E_UNKNOWN_TYPE', 'E_BAD_BET', 'E_BAD_SEED', 'E_NOT_IN_ROOM', 'E_UNKNOWN_ROOM']))

    expect(await ledgerTotals(backend, database.database)).toEqual(before)
    for (const [i, p] of players.entries()) {
      const me = await server.api('GET', '/api/me', { token: p.token })
      expect({ balance: me.body.balance, nonce: me.body.nonce }).toEqual({ balance: balances[i].body.balance, nonce: balances[i].body.nonce })
    }
    await Promise.all(players.map((p) => p.client.close()))
  })

  /** A fresh connection sends `send(socket)` and must be closed with `code`. */
  async function expectClose (send, code) {
    const { client } = await server.player('8-low')
    send(client.socket)
    const closed = await client.closed
    expect(closed.code).toBe(code)
  }

  it('closes frames it cannot accept with the proper close code and keeps serving', async () => {
    const before = await ledgerTotals(backend, database.database)
    // 1 MB text and binary frames: over maxPayload → 1009.
    await expectClose((s) => s.send(JSON.stringify({ type: 'drop', bet: 1, clientSeed: 'x'.repeat(1 << 20) })), 1009)
    await expectClose((s) => s.send(Buffer.alloc(1 << 20), { binary: true }), 1009)
    // Invalid UTF-8 in a text frame (a client seed with a lone continuation byte / overlong encoding) → 1007.
    for (const bytes of [[0x80], [0xc0, 0xaf], [0xed, 0xa0, 0x80], [0xff, 0xfe]]) {
      const text = Buffer.concat([Buffer.from('{"type":"drop","bet":1,"clientSeed":"a'), Buffer.from(bytes), Buffer.from('"}')])
      await expectClose((s) => s.send(text, { binary: false }), 1007)
    }
    // Protocol violations written straight to the TCP socket → 1002: a reserved opcode, an unmasked frame, RSV bits.
    const mask = [1, 2, 3, 4]
    await expectClose((s) => s._socket.write(Buffer.from([0x83, 0x80, ...mask])), 1002)
    await expectClose((s) => s._socket.write(Buffer.from([0x81, 0x02, 0x7b, 0x7d])), 1002)
    await expectClose((s) => s._socket.write(Buffer.from([0xc1, 0x80, ...mask])), 1002)
    // A fragmented control frame (ping without FIN) → 1002.
    await expectClose((s) => s._socket.write(Buffer.from([0x09, 0x80, ...mask])), 1002)
    expect(await ledgerTotals(backend, database.database)).toEqual(before)
  })

  it('refuses messages before authentication and sockets without a valid token', async () => {
    // Frames sent before the welcome are queued, then answered in order; a flood is closed with 1008.
    const session = await server.session()
    const early = new GameClient(server.wsUrl(session.token))
    await early.opened
    early.send('{nope')
    early.send({ type: 'drop', bet: 1 })
    await early.take('welcome')
    expect((await early.take('error')).code).toBe('E_BAD_MESSAGE')
    expect((await early.take('error')).code).toBe('E_NOT_IN_ROOM')
    await early.close()

    const flood = new WebSocket(server.wsUrl('0'.repeat(64)))
    await new Promise((resolve) => flood.once('open', resolve))
    for (let i = 0; i < 100; i++) flood.send('{"type":"ping"}')
    const code = await new Promise((resolve) => flood.once('close', resolve))
    expect([1008, 4401]).toContain(code)
  })

  it('still lets a fresh player play afterwards, with a consistent ledger', async () => {
    const { client, session } = await server.player('12-medium')
    client.send({ type: 'drop', bet: 100, ref: 'after-fuzz' })
    const dropped = await client.take('dropped')
    expect(dropped.ref).toBe('after-fuzz')
    const settled = await client.take('settled')
    expect(Math.round(settled.balance * 1000)).toBe((100000 - 100) * 1000 + Math.round(settled.payout * 1000)) // summed in milli-credits
    const ledger = await expectConsistentLedger(expect, backend, database.database, { playerIds: [session.playerId], startingBalance: 100000 })
    expect(ledger.size).toBe(1)
    await client.close()
  })
})
