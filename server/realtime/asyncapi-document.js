import { clientMessageSchemas } from '../../protocol/client-messages.js'
import { ERROR_CODES } from '../errors.js'
import { SNAPSHOT_KIND, ROOM_FRAME_KIND } from '../../protocol/snapshot-codec.js'
import { DROP_EVENTS_KIND } from '../../protocol/drop-events-codec.js'
import { DELIVERY_MODES } from '../../protocol/client-messages.js'

/**
 * The WebSocket protocol (GET /ws) as an AsyncAPI 3.0 document, served at
 * /api/asyncapi.json and rendered at /docs/websocket. The client → server
 * messages are the very schemas the server validates every frame against
 * (protocol/client-messages.js, with this server's bet limits); the
 * server → client messages are described here, and tests/docs/ checks the
 * messages a real session receives against these schemas (no unknown field
 * passes), so the document cannot drift from what the server sends.
 */

const string = { type: 'string' }
const integer = { type: 'integer' }
/** Balances and payouts: credits, with up to three decimals (bets are whole credits). */
const credits = { type: 'number', description: 'credits, up to three decimals' }
const hash = { type: 'string', pattern: '^[0-9a-f]{64}$' }
const ref = { description: 'the `ref` of the request this answers, echoed', anyOf: [{ type: 'string', maxLength: 64 }, { type: 'integer' }] }

const object = (properties, required = Object.keys(properties), optional = {}) => ({
  type: 'object',
  properties: { ...properties, ...optional },
  required,
  additionalProperties: false
})

/** The facts every client needs to replay a drop: what `dropped` and `joined.balls` carry. */
const dropFacts = {
  dropId: integer,
  player: string,
  slot: { type: 'integer', minimum: 0, description: 'the ball\'s per-room number in snapshot frames' },
  serverSeedHash: hash,
  clientSeed: string,
  nonce: integer,
  dropSeed: hash,
  engineVersion: string,
  bet: integer,
  startTick: integer
}

const droppedFields = { type: { const: 'dropped' }, room: string, ...dropFacts }
const settledFields = {
  type: { const: 'settled' },
  room: string,
  dropId: integer,
  player: string,
  bet: integer,
  bucket: integer,
  multiplier: { type: 'number' },
  payout: credits,
  ticks: integer,
  tick: { type: 'integer', description: '`startTick + ticks`' },
  stateHash: string
}
const ownerExtras = { balance: { ...credits, description: 'the owner\'s balance in credits after this event (to the owner\'s connections only)' }, ref }

/** JSON schemas of every server → client text message, by type. */
export const SERVER_MESSAGE_SCHEMAS = Object.freeze({
  welcome: {
    summary: 'First message of every authenticated connection',
    payload: object({
      type: { const: 'welcome' },
      playerId: string,
      balance: credits,
      serverSeedHash: hash,
      clientSeed: string,
      nonce: integer,
      engineVersion: string,
      tickRate: { const: 60 },
      minBet: integer,
      maxBet: integer
    })
  },
  joined: {
    summary: 'Reply to `join`: the room, its board and every ball in flight',
    payload: object({
      type: { const: 'joined' },
      room: string,
      delivery: { enum: DELIVERY_MODES, description: 'how this socket is fed in the room: `join.delivery`, default "snapshots"' },
      board: { type: 'object', description: "the room's board (engine `createBoard` data): replay drops with `simulateDrop(board, dropSeed)`" },
      tick: integer,
      tickRate: { const: 60 },
      snapshotEvery: { type: 'integer', description: 'ticks between two snapshot frames (60 / SNAPSHOT_HZ)' },
      engineVersion: string,
      balls: { type: 'array', items: object({ ...dropFacts, x: { type: 'number' }, y: { type: 'number' } }) }
    }, ['type', 'room', 'delivery', 'board', 'tick', 'tickRate', 'snapshotEvery', 'engineVersion', 'balls'], {
      ref,
      eventEvery: { type: 'integer', description: 'seeds delivery: ticks between two drop-events frames at most often (60 / EVENT_HZ)' },
      checkEvery: { type: 'integer', description: 'seeds delivery: most ticks between two desync checks while balls are in flight (2 s)' },
      engineVersions: { type: 'array', items: string, description: 'seeds delivery: the table the drop-events frame\'s engine index points into' }
    })
  },
  left: {
    summary: 'Reply to `leave`',
    payload: object({ type: { const: 'left' }, room: string }, ['type', 'room'], { ref })
  },
  pong: {
    summary: 'Reply to `ping`; a socket in a room also gets the room and its tick as the reply is sent (a sample for the page\'s room clock when nothing else names a tick)',
    payload: object({
      type: { const: 'pong' },
      serverTime: { type: 'integer', description: 'the server\'s clock, epoch ms' },
      room: { type: 'string', description: 'the socket\'s room (only when it is in one)' },
      tick: { type: 'integer', minimum: 0, description: 'that room\'s tick when the reply was sent (only with `room`)' }
    }, ['type', 'serverTime'], { ref })
  },
  dropped: {
    summary: 'A drop was recorded (its bet debited): to the owner at once, to snapshots-mode sockets in the room with its next snapshot (seeds-mode sockets get other players\' drops in drop-events frames)',
    payload: object(droppedFields, Object.keys(droppedFields), ownerExtras)
  },
  settled: {
    summary: 'A drop landed and its payout was credited: to the owner at once (seeds-mode sockets in the drop\'s room: in the owner\'s section of the room\'s next drop-events frame), to snapshots-mode sockets in the room with its next snapshot',
    payload: object(settledFields, Object.keys(settledFields), ownerExtras)
  },
  events: {
    summary: "The room's events of one snapshot period, when no room frame carries them",
    payload: object({
      type: { const: 'events' },
      room: string,
      events: { type: 'array', items: { oneOf: [object(droppedFields), object(settledFields)] } }
    })
  },
  balance: {
    summary: "Clustered only: another process changed this player's committed balance",
    payload: object({ type: { const: 'balance' }, balance: credits })
  },
  error: {
    summary: 'A refused message, or why the connection is about to close',
    payload: object({
      type: { const: 'error' },
      code: { type: 'string', enum: Object.keys(ERROR_CODES) },
      message: string
    }, ['type', 'code', 'message'], {
      ref,
      room: { type: 'string', description: 'E_WRONG_NODE, E_ROOM_MOVING: the room asked for' },
      owner: { type: 'string', description: 'E_WRONG_NODE: the URL of the process that runs the room; reconnect to `owner + "/ws?token=…"`' },
      retryAfterMs: { type: 'integer', description: 'E_ROOM_MOVING: join again after this long' }
    })
  }
})

/**
 * The binary frames, described (their layout is in docs/protocol.md); each
 * names its first byte (`x-frame-kind`), so a client (and the protocol test)
 * can tell the frames apart.
 */
const BINARY_MESSAGES = {
  snapshot: {
    kind: SNAPSHOT_KIND,
    summary: 'Snapshot frame: every visible ball\'s position in a room',
    description: 'Binary, little-endian: kind = 1 (uint8), room tick (uint32), S = highest visible slot + 1 (uint16), a presence bitmask of ⌈S/8⌉ bytes, then x and y of each present slot as 11-bit values of round(px·2), packed least-significant bit first. Sent every `snapshotEvery` ticks; decode with protocol/snapshot-codec.js.'
  },
  dropEvents: {
    kind: DROP_EVENTS_KIND,
    summary: 'Drop-events frame (seeds delivery): other players\' drops and a desync check, instead of positions',
    description: 'Binary, little-endian: kind = 3 (uint8), room tick (uint32), flight hash (two uint32 words), N (uint16), then N events of 64 bytes: drop id (uint64), bet (uint64), start tick (uint32), slot (uint16), engine version index (uint8), flags (uint8), player id (8 bytes), drop seed (32 bytes); then, in the owner\'s copy only, the owner\'s section: the rest of the frame is an ASCII JSON array of this player\'s own messages (its `settled` in this room, with `balance`), handled after the events as if each had come on its own. At most one every `eventEvery` ticks with the drops announced since the previous frame (due on the room\'s grid of `eventEvery` ticks, it waits up to `eventEvery / 2` ticks while a drop released before it is still being committed (not once a drop it carries was released more than `eventEvery` ticks before) and goes once that commit is done, stamped with the room\'s tick then; within that a tick or two more while other rooms\' frames released by the same commit go out); with no events, at most every `checkEvery` ticks while balls are in flight. The flight hash is defined in protocol/drop-events-codec.js, which decodes the frame (`decodeDropEvents`).'
  },
  roomFrame: {
    kind: ROOM_FRAME_KIND,
    summary: 'Room frame: the period\'s events and a snapshot in one binary frame',
    description: 'Binary, little-endian: kind = 2 (uint8), L (uint32), the events (`dropped`, `settled`) as a UTF-8 JSON array of L bytes, oldest first, then a snapshot frame. Split with protocol/snapshot-codec.js (`splitRoomFrame`).'
  }
}

/**
 * What the client sends, what answers it, and examples a server accepts (a
 * player with a fresh session; `drop` and `leave` once in a room): the
 * protocol test sends each one, and each value of an optional field that
 * has a closed set of values (enum, const, boolean).
 * @param {{ minBet: number }} config
 */
const clientMessageDocs = ({ minBet }) => ({
  join: {
    summary: 'Join a room: `ROWS-RISK` (e.g. `16-medium`) or an instance `ROWS-RISK.N` (N 2–8); `delivery` "snapshots" (default: positions) or "seeds" (drop events only, the page simulates)',
    reply: ['joined', 'error'],
    examples: [{ name: 'room', payload: { type: 'join', room: '16-medium' } }, { name: 'instance', payload: { type: 'join', room: '8-low.2', ref: 1 } }, { name: 'seeds delivery', payload: { type: 'join', room: '16-medium', delivery: 'seeds' } }]
  },
  leave: { summary: 'Leave the room', reply: ['left', 'error'], examples: [{ name: 'leave', payload: { type: 'leave' } }] },
  drop: {
    summary: 'Drop a ball: `bet` credits; a `clientSeed` becomes the player\'s client seed in the drop\'s own transaction',
    reply: ['dropped', 'error'],
    examples: [{ name: 'bet', payload: { type: 'drop', bet: minBet } }, { name: 'with a client seed', payload: { type: 'drop', bet: minBet, clientSeed: 'my lucky seed', ref: 'd1' } }]
  },
  ping: { summary: 'Round trip; counts against the frame rate like any frame', reply: ['pong'], examples: [{ name: 'ping', payload: { type: 'ping', ref: 'p1' } }] }
})

/** WebSocket close codes the server uses. */
export const CLOSE_CODES = Object.freeze({
  1001: 'server shutting down',
  1002: 'protocol error (bad frame)',
  1007: 'invalid UTF-8',
  1008: 'policy: over the frame rate (E_RATE_LIMITED) or a flood before authentication',
  1009: 'frame larger than WS_MAX_PAYLOAD',
  1011: 'internal error while authenticating',
  1013: 'slow client (E_SLOW_CONSUMER)',
  4401: 'unauthorized (E_UNAUTHORIZED)',
  4429: 'too many connections (E_TOO_MANY_CONNECTIONS)'
})

/**
 * @param {{ minBet: number, maxBet: number, wsMaxPayload: number }} config
 * @param {{ version: string, host: string }} where this server's version and the host clients reach it at
 */
export function asyncApiDocument (config, { version, host }) {
  const clientSchemas = clientMessageSchemas(config)
  const clientDocs = clientMessageDocs(config)
  const messages = {}
  for (const [type, schema] of Object.entries(clientSchemas)) {
    const examples = clientDocs[type]?.examples
    messages[type] = { name: type, title: `${type} (client → server)`, summary: clientDocs[type]?.summary ?? type, contentType: 'application/json', payload: schema, ...(examples ? { examples } : {}) }
  }
  for (const [type, { summary, payload }] of Object.entries(SERVER_MESSAGE_SCHEMAS)) {
    messages[type] = { name: type, title: `${type} (server → client)`, summary, contentType: 'application/json', payload }
  }
  for (const [name, { kind, summary, description }] of Object.entries(BINARY_MESSAGES)) {
    messages[name] = { name, title: `${name} (server → client, binary)`, summary, description, contentType: 'application/octet-stream', payload: { type: 'string', format: 'binary' }, 'x-frame-kind': kind }
  }
  const channelRef = { $ref: '#/channels/game' }
  const messageRef = (name) => ({ $ref: `#/channels/game/messages/${name}` })
  const operations = {}
  for (const type of Object.keys(clientSchemas)) {
    operations[`receive-${type}`] = {
      action: 'receive',
      title: `Client sends ${type}`,
      summary: clientDocs[type]?.summary ?? type,
      channel: channelRef,
      messages: [messageRef(type)],
      ...(clientDocs[type]?.reply ? { reply: { channel: channelRef, messages: clientDocs[type].reply.map(messageRef) } } : {})
    }
  }
  for (const name of [...Object.keys(SERVER_MESSAGE_SCHEMAS), ...Object.keys(BINARY_MESSAGES)]) {
    if (['joined', 'left', 'pong'].includes(name)) continue // only ever replies, listed with their requests
    operations[`send-${name}`] = { action: 'send', title: `Server sends ${name}`, summary: messages[name].summary, channel: channelRef, messages: [messageRef(name)] }
  }
  return {
    asyncapi: '3.0.0',
    info: {
      title: 'Plinko Arena game protocol',
      version,
      description: [
        'The real-time protocol of GET /ws?token=SESSION_TOKEN (create a token with POST /api/session).',
        `Client messages are JSON text frames of at most ${config.wsMaxPayload} bytes, checked against the schemas below before any handler runs (unknown properties are refused); each may carry \`ref\`, echoed in the direct reply.`,
        'A bad or missing token still upgrades, then gets an `error` E_UNAUTHORIZED and close code 4401.',
        'Refused messages change nothing: no debit, no nonce, no ledger row.',
        `Close codes: ${Object.entries(CLOSE_CODES).map(([code, why]) => `${code} ${why}`).join('; ')}.`
      ].join('\n\n')
    },
    defaultContentType: 'application/json',
    servers: {
      game: {
        host,
        protocol: 'ws',
        pathname: '/ws',
        description: 'This server (wss behind a TLS proxy)',
        bindings: { ws: { query: { type: 'object', properties: { token: { type: 'string', maxLength: 128, description: 'session token from POST /api/session' } }, required: ['token'] } } }
      }
    },
    channels: {
      game: {
        address: '/ws',
        title: 'The game connection',
        description: 'One connection per browser tab; join one room at a time.',
        servers: [{ $ref: '#/servers/game' }],
        messages
      }
    },
    operations
  }
}

/** HTML-escaped text. @param {unknown} value */
const escape = (value) => String(value).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c])

/** A schema's fields as table rows: name, type and constraints, required. */
function fieldRows (schema) {
  const required = new Set(schema.required ?? [])
  return Object.entries(schema.properties ?? {}).map(([name, field]) => {
    const facts = []
    if (field.const !== undefined) facts.push(`= ${JSON.stringify(field.const)}`)
    else if (field.anyOf || field.oneOf) facts.push((field.anyOf ?? field.oneOf).map((f) => f.type ?? 'object').join(' | '))
    else facts.push(Array.isArray(field.type) ? field.type.join(' | ') : field.type ?? 'any')
    for (const key of ['minimum', 'maximum', 'maxLength', 'pattern']) if (field[key] !== undefined) facts.push(`${key} ${field[key]}`)
    if (field.enum) facts.push(`one of ${field.enum.join(', ')}`)
    if (field.items?.properties) facts.push(`items: { ${Object.keys(field.items.properties).join(', ')} }`)
    return `<tr><td><code>${escape(name)}</code></td><td>${escape(facts.join('; '))}</td><td>${required.has(name) ? 'yes' : ''}</td><td>${escape(field.description ?? '')}</td></tr>`
  }).join('\n')
}

/**
 * The AsyncAPI document as one static HTML page (no script, so it passes the
 * app's Content-Security-Policy as it is).
 * @param {ReturnType<typeof asyncApiDocument>} document
 */
export function asyncApiPage (document) {
  const messages = document.channels.game.messages
  const section = (message) => `<section id="${escape(message.name)}">
<h3>${escape(message.title)}</h3>
<p>${escape(message.summary)}</p>
${message.description ? `<p>${escape(message.description)}</p>` : ''}
${message.examples ? `<p>Examples: ${message.examples.map((example) => `<code>${escape(JSON.stringify(example.payload))}</code>`).join(', ')}</p>` : ''}
${message.payload.properties ? `<table><thead><tr><th>field</th><th>type</th><th>required</th><th></th></tr></thead><tbody>\n${fieldRows(message.payload)}\n</tbody></table>` : ''}
</section>`
  const replies = Object.values(document.operations).filter((op) => op.action === 'receive')
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<link rel="icon" href="data:,">
<title>${escape(document.info.title)}</title>
<style>body{font-family:system-ui,sans-serif;max-width:60rem;margin:2rem auto;padding:0 1rem;line-height:1.4}table{border-collapse:collapse;margin:.5rem 0 1.5rem}td,th{border:1px solid #ccc;padding:.2rem .5rem;text-align:left;vertical-align:top}code{font-size:.95em}</style>
</head>
<body>
<h1>${escape(document.info.title)} <small>${escape(document.info.version)}</small></h1>
${document.info.description.split('\n\n').map((p) => `<p>${escape(p)}</p>`).join('\n')}
<p>Machine-readable: <a href="/api/asyncapi.json">/api/asyncapi.json</a> (AsyncAPI ${escape(document.asyncapi)}). HTTP API: <a href="/docs">/docs</a>.</p>
<h2>Client → server</h2>
<table><thead><tr><th>message</th><th>answered by</th></tr></thead><tbody>
${replies.map((op) => `<tr><td><a href="#${escape(op.messages[0].$ref.split('/').pop())}">${escape(op.messages[0].$ref.split('/').pop())}</a></td><td>${(op.reply?.messages ?? []).map((m) => m.$ref.split('/').pop()).map((name) => `<a href="#${escape(name)}">${escape(name)}</a>`).join(', ')}</td></tr>`).join('\n')}
</tbody></table>
${Object.values(messages).filter((m) => m.title.includes('client → server')).map(section).join('\n')}
<h2>Server → client</h2>
${Object.values(messages).filter((m) => m.title.includes('server → client')).map(section).join('\n')}
<h2>Error codes</h2>
<table><thead><tr><th>code</th><th>HTTP status</th><th>close code</th><th>message</th></tr></thead><tbody>
${Object.entries(ERROR_CODES).map(([code, { status, close, message }]) => `<tr><td><code>${code}</code></td><td>${status}</td><td>${close ?? ''}</td><td>${escape(message)}</td></tr>`).join('\n')}
</tbody></table>
</body>
</html>
`
}
