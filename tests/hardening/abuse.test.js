import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { createHash } from 'node:crypto'
import fs from 'node:fs'
import net from 'node:net'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import WebSocket from 'ws'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer, eventually, OPERATOR_TOKEN } from '../server/helpers/server.js'
import { GameClient } from '../server/helpers/game-client.js'
import { expectConsistentLedger } from './helpers/ledger.js'

/**
 * Abuse: rate limits (HTTP per IP, sessions per IP, drops per player,
 * frames per connection), connection limits, maxPayload, heartbeats,
 * security headers, the operator API's token and its secrecy, slow and
 * vanished clients. One small server per concern, each with the limit under
 * test set low through its environment variable.
 */
const CLIENT_DIR = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../client')
const backend = storeBackend('sqlite')
const servers = []

beforeAll(async () => { await backend.setup() })
afterAll(async () => {
  for (const server of servers) await server.close().catch(() => {})
  await backend.teardown()
})

async function serverWith (env, options = {}) {
  const database = await backend.newDatabase()
  const server = await startServer(database, { env, ...options })
  server.database = database
  servers.push(server)
  return server
}

/** A plain TCP connection to the HTTP port, recording what it receives and when it closes. */
async function rawTcp (port) {
  const socket = net.connect(port, '127.0.0.1')
  await new Promise((resolve, reject) => { socket.once('connect', resolve); socket.once('error', reject) })
  const chunks = []
  socket.on('data', (chunk) => chunks.push(chunk))
  socket.on('error', () => {})
  const closed = new Promise((resolve) => socket.once('close', resolve))
  return {
    socket,
    received: () => Buffer.concat(chunks).toString('latin1'),
    closedWithin: (ms) => Promise.race([closed.then(() => true), new Promise((resolve) => setTimeout(() => resolve(false), ms))]).finally(() => socket.destroy())
  }
}

/** A raw socket that records its close code and the JSON messages it got. */
function rawSocket (url, options) {
  const socket = new WebSocket(url, options)
  const messages = []
  socket.on('message', (data, isBinary) => { if (!isBinary) messages.push(JSON.parse(data.toString())) })
  const closed = new Promise((resolve) => socket.once('close', (code) => resolve(code)))
  socket.on('error', () => {})
  return { socket, messages, closed }
}

describe('rate limits', () => {
  it('limits HTTP requests per IP (429 E_RATE_LIMITED with retry-after), each IP on its own', async () => {
    const server = await serverWith({ HTTP_RATE_LIMIT: '5' })
    const get = (ip) => server.app.inject({ method: 'GET', url: '/api/rooms', remoteAddress: ip })
    for (let i = 0; i < 5; i++) expect((await get('10.0.0.1')).statusCode).toBe(200)
    const limited = await get('10.0.0.1')
    expect(limited.statusCode).toBe(429)
    expect(limited.json()).toMatchObject({ code: 'E_RATE_LIMITED' })
    expect(Number(limited.headers['retry-after'])).toBeGreaterThan(0)
    expect((await get('10.0.0.2')).statusCode).toBe(200)
    // Liveness is exempt, so a load balancer's probes never fail.
    expect((await server.app.inject({ method: 'GET', url: '/api/health', remoteAddress: '10.0.0.1' })).statusCode).toBe(200)
  })

  it('limits new sessions per IP', async () => {
    const server = await serverWith({ SESSION_RATE_LIMIT: '2' })
    const post = (ip) => server.app.inject({ method: 'POST', url: '/api/session', remoteAddress: ip })
    expect((await post('10.0.0.3')).statusCode).toBe(201)
    expect((await post('10.0.0.3')).statusCode).toBe(201)
    expect((await post('10.0.0.3')).json()).toMatchObject({ code: 'E_RATE_LIMITED' })
    expect((await post('10.0.0.4')).statusCode).toBe(201)
  })

  it('limits drops per player across all of its connections', async () => {
    const server = await serverWith({ DROP_RATE: '1', DROP_BURST: '5' })
    const { client, token } = await server.player('8-low')
    const second = await server.connect(token)
    second.send({ type: 'join', room: '9-low' })
    await second.take('joined')
    for (let i = 0; i < 5; i++) { client.send({ type: 'drop', bet: 1 }); second.send({ type: 'drop', bet: 1 }) }
    await client.sync()
    await second.sync()
    const errors = [...client.messages, ...second.messages].filter((m) => m.type === 'error')
    expect(errors.length).toBeGreaterThanOrEqual(4)
    expect(errors.every((m) => m.code === 'E_RATE_LIMITED')).toBe(true)
  })

  it('limits drops per IP across all of its players and sessions, and debits nothing refused', async () => {
    const server = await serverWith({ DROP_RATE: '1000', DROP_BURST: '1000', DROP_RATE_PER_IP: '2' }) // burst: 4
    const players = [await server.player('8-low'), await server.player('9-low')]
    for (let i = 0; i < 6; i++) for (const { client } of players) client.send({ type: 'drop', bet: 1 })
    const answered = () => players.flatMap(({ client }) => client.messages).filter((m) => m.type === 'dropped' || m.type === 'error').length
    await eventually(() => answered() >= 12)
    const messages = players.flatMap(({ client }) => client.messages)
    const accepted = messages.filter((m) => m.type === 'dropped').length // each player is alone in its room
    const refused = messages.filter((m) => m.type === 'error')
    expect(refused.every((m) => m.code === 'E_RATE_LIMITED' && /one address/.test(m.message))).toBe(true)
    expect(accepted).toBeGreaterThanOrEqual(4)
    expect(accepted).toBeLessThanOrEqual(6) // the burst, plus what 2/s refills while the frames arrive
    expect(accepted + refused.length).toBe(12)
    // Closing and reopening a socket does not hand the address a fresh burst.
    await players[0].client.close()
    const again = await server.connect(players[0].token)
    again.send({ type: 'join', room: '8-low' })
    await again.take('joined')
    for (let i = 0; i < 3; i++) again.send({ type: 'drop', bet: 1 })
    await eventually(() => again.messages.filter((m) => (m.type === 'dropped' && m.player === again.welcome.playerId) || m.type === 'error').length >= 3)
    expect(again.messages.filter((m) => m.code === 'E_RATE_LIMITED').length).toBeGreaterThanOrEqual(2)
    const acceptedAgain = again.messages.filter((m) => m.type === 'dropped' && m.player === again.welcome.playerId).length
    const settledInLedger = async () => {
      const [row] = await backend.query(server.database.database, "SELECT count(*) AS n, sum(CASE WHEN status = 'settled' THEN 1 ELSE 0 END) AS settled FROM drops")
      return Number(row.n) === accepted + acceptedAgain && Number(row.settled) === Number(row.n)
    }
    await eventually(settledInLedger)
    await expectConsistentLedger(expect, backend, server.database.database, { playerIds: players.map(({ client }) => client.welcome.playerId), startingBalance: 100000 })
  })

  it('limits joins per player and per IP', async () => {
    const perPlayer = await serverWith({ JOIN_RATE: '1', JOIN_RATE_PER_IP: '1000' }) // burst: 2 per player
    const { client } = await perPlayer.player()
    for (let i = 0; i < 6; i++) client.send({ type: 'join', room: i % 2 ? '8-low' : '8-high' })
    await eventually(() => client.messages.filter((m) => m.type === 'joined' || m.type === 'error').length >= 6)
    expect(client.messages.filter((m) => m.type === 'joined').length).toBeLessThanOrEqual(3)
    expect(client.messages.filter((m) => m.code === 'E_RATE_LIMITED' && /per player/.test(m.message)).length).toBeGreaterThanOrEqual(3)
    const other = await perPlayer.player()
    other.client.send({ type: 'join', room: '8-low' })
    await other.client.take('joined') // another player from the same address is not held back

    const perIp = await serverWith({ JOIN_RATE: '1000', JOIN_RATE_PER_IP: '1' }) // burst: 2 per address
    const first = await perIp.player()
    const second = await perIp.player()
    for (let i = 0; i < 3; i++) { first.client.send({ type: 'join', room: '8-low' }); second.client.send({ type: 'join', room: '9-low' }) }
    await eventually(() => [first, second].every(({ client }) => client.messages.filter((m) => m.type === 'joined' || m.type === 'error').length >= 3))
    const all = [...first.client.messages, ...second.client.messages]
    expect(all.filter((m) => m.type === 'joined').length).toBeLessThanOrEqual(3)
    expect(all.filter((m) => m.code === 'E_RATE_LIMITED' && /one address/.test(m.message)).length).toBeGreaterThanOrEqual(3)
  })

  it('limits frames (joins, pings, anything) per connection: one E_RATE_LIMITED, then close 1008', async () => {
    const server = await serverWith({ WS_MESSAGE_RATE: '2', WS_MESSAGE_BURST: '10', JOIN_RATE: '1000' })
    const { client } = await server.player()
    for (let i = 0; i < 40; i++) client.send({ type: 'join', room: i % 2 ? '8-low' : '8-high', ref: i })
    const { code, reason } = await client.closed
    const joined = client.messages.filter((m) => m.type === 'joined').length
    const limited = client.messages.filter((m) => m.code === 'E_RATE_LIMITED')
    expect(joined).toBeGreaterThanOrEqual(10)
    expect(joined).toBeLessThan(20)
    expect(limited).toHaveLength(1)
    expect(limited[0].message).toMatch(/per connection; closing/)
    expect({ code, reason }).toEqual({ code: 1008, reason: 'E_RATE_LIMITED' })
    // Nothing is answered after the refusal.
    expect(client.messages.indexOf(limited[0])).toBe(client.messages.length - 1)

    // Protocol-level pings count too.
    const pinger = await server.player()
    for (let i = 0; i < 40; i++) pinger.client.socket.ping()
    expect((await pinger.client.closed).code).toBe(1008)
    expect(pinger.client.messages.filter((m) => m.code === 'E_RATE_LIMITED')).toHaveLength(1)
  })
})

describe('connection limits, payload and heartbeats', () => {
  it('closes an HTTP connection that sends nothing (HTTP_IDLE_TIMEOUT_MS) and one that sends its request too slowly (HTTP_REQUEST_TIMEOUT_MS)', async () => {
    const server = await serverWith({ HTTP_IDLE_TIMEOUT_MS: '300', HTTP_REQUEST_TIMEOUT_MS: '800' })
    const idle = await rawTcp(server.port)
    expect(await idle.closedWithin(3000)).toBe(true)
    // Slowloris: a header line every 100 ms keeps the socket busy, but the request never completes.
    const slow = await rawTcp(server.port)
    slow.socket.write('GET /api/rooms HTTP/1.1\r\nHost: localhost\r\n')
    const drip = setInterval(() => { if (!slow.socket.destroyed) slow.socket.write('X-Slow: 1\r\n') }, 100)
    try {
      expect(await slow.closedWithin(5000)).toBe(true)
      expect(slow.received()).toMatch(/^HTTP\/1\.1 408/)
    } finally {
      clearInterval(drip)
    }
    // A normal request on a fresh connection is unaffected.
    expect((await fetch(`http://127.0.0.1:${server.port}/api/rooms`)).status).toBe(200)
  })

  it('refuses WebSockets over the per-IP limit with E_TOO_MANY_CONNECTIONS and close 4429, and frees the slot on close', async () => {
    const server = await serverWith({ WS_MAX_CONNECTIONS_PER_IP: '3' })
    const session = await server.session()
    const open = []
    for (let i = 0; i < 3; i++) open.push(await server.connect(session.token))
    const refused = rawSocket(server.wsUrl(session.token))
    expect(await refused.closed).toBe(4429)
    expect(refused.messages).toEqual([expect.objectContaining({ type: 'error', code: 'E_TOO_MANY_CONNECTIONS' })])
    // Unauthenticated sockets count too: no free slots by opening sockets without a token.
    expect(await rawSocket(server.wsUrl()).closed).toBe(4429)
    await open[0].close()
    await eventually(async () => {
      const again = rawSocket(server.wsUrl(session.token))
      await new Promise((resolve) => setTimeout(resolve, 50))
      const ok = again.messages.some((m) => m.type === 'welcome')
      again.socket.close()
      await again.closed
      return ok
    })
  })

  it('refuses WebSockets over the total limit', async () => {
    const server = await serverWith({ WS_MAX_CONNECTIONS: '2', WS_MAX_CONNECTIONS_PER_IP: '100' })
    const session = await server.session()
    await server.connect(session.token)
    await server.connect(session.token)
    const refused = rawSocket(server.wsUrl(session.token))
    expect(await refused.closed).toBe(4429)
  })

  it('closes a frame over WS_MAX_PAYLOAD with 1009 and accepts one under it', async () => {
    const server = await serverWith({ WS_MAX_PAYLOAD: '512' })
    const { client } = await server.player()
    client.send({ type: 'ping', ref: 'x'.repeat(60) })
    await client.take('pong')
    client.send({ type: 'join', room: 'x'.repeat(600) })
    expect((await client.closed).code).toBe(1009)
  })

  it('drops a peer that stops answering pings (WS_HEARTBEAT_MS) and keeps one that answers', async () => {
    const server = await serverWith({ WS_HEARTBEAT_MS: '300' })
    const session = await server.session()
    const healthy = await server.connect(session.token)
    const silent = rawSocket(server.wsUrl(session.token), { autoPong: false })
    let pings = 0
    silent.socket.on('ping', () => pings++)
    const code = await silent.closed
    expect(pings).toBeGreaterThanOrEqual(1)
    expect(code).toBe(1006) // terminated, no close frame: the peer is presumed gone
    await healthy.sync()
    expect(healthy.closeEvent).toBeNull()
  })
})

describe('security headers', () => {
  it('sends helmet headers, and a CSP that allows exactly the client page\'s inline scripts', async () => {
    const server = await serverWith({ CLIENT_DIR })
    for (const url of ['/api/health', '/']) {
      const response = await server.api('GET', url)
      expect(response.status).toBe(200)
      expect(response.headers['x-content-type-options']).toBe('nosniff')
      expect(response.headers['x-frame-options']).toBe('SAMEORIGIN')
      expect(response.headers['strict-transport-security']).toMatch(/max-age=\d+/)
      expect(response.headers['referrer-policy']).toBe('no-referrer')
      const csp = response.headers['content-security-policy']
      expect(csp).toMatch(/default-src 'self'/)
      expect(csp).toMatch(/object-src 'none'/)
      expect(csp).toMatch(/frame-ancestors 'self'/)
      const scriptSrc = /script-src ([^;]*)/.exec(csp)[1]
      expect(scriptSrc).not.toMatch(/unsafe-inline|unsafe-eval/)
      if (url === '/') {
        // Every inline script of the page is allowed by its hash (else the browser would refuse it).
        const inline = [...response.text.matchAll(/<script(?![^>]*\bsrc=)[^>]*>([\s\S]*?)<\/script>/g)].map((m) => m[1])
        for (const source of inline) expect(scriptSrc).toContain(`'sha256-${createHash('sha256').update(source).digest('base64')}'`)
      }
    }
    expect(fs.existsSync(path.join(CLIENT_DIR, 'index.html'))).toBe(true)
  })
})

describe('operator API', () => {
  it('refuses without the operator token (401) or with a wrong one, including a player token (403)', async () => {
    const server = await serverWith({})
    const { session, client } = await server.player('8-low')
    client.send({ type: 'drop', bet: 1 })
    const dropped = await client.take('dropped')
    const urls = [`/api/audit/drops/${dropped.dropId}`, '/api/audit/drops', '/api/audit/verify?serverSeed=a&clientSeed=b&nonce=0', `/api/audit/export?player=${session.playerId}`, '/api/audit/rooms/8-low/stats']
    for (const url of urls) {
      expect((await server.api('GET', url)).body).toMatchObject({ code: 'E_UNAUTHORIZED' })
      for (const token of ['wrong-token', session.token, OPERATOR_TOKEN.slice(0, -1), OPERATOR_TOKEN + 'x']) {
        const response = await server.api('GET', url, { token })
        expect(response.status).toBe(403)
        expect(response.body.code).toBe('E_FORBIDDEN')
      }
      expect((await server.api('GET', url, { token: OPERATOR_TOKEN })).status).toBe(200)
    }
  })

  it('never returns an unrevealed server seed, to the operator or to the player', async () => {
    const server = await serverWith({})
    const { session, client, token } = await server.player('10-high')
    for (let i = 0; i < 3; i++) client.send({ type: 'drop', bet: 5 })
    for (let i = 0; i < 3; i++) await client.take('settled')
    const [active] = await backend.query(server.database.database, 'SELECT seed, hash FROM server_seeds WHERE player_id = $1 AND active = 1', [session.playerId])
    const ids = client.messages.filter((m) => m.type === 'dropped').map((m) => m.dropId)
    const operatorUrls = [...ids.map((id) => `/api/audit/drops/${id}`), `/api/audit/drops?player=${session.playerId}`, `/api/audit/export?player=${session.playerId}`,
      `/api/audit/export?player=${session.playerId}&format=ndjson`, `/api/audit/export?serverSeedHash=${active.hash}`, '/api/audit/rooms/10-high/stats', '/metrics']
    const playerUrls = ['/api/me', '/api/seeds', '/api/drops', ...ids.map((id) => `/api/drops/${id}`)]
    const texts = []
    for (const url of operatorUrls) texts.push((await server.api('GET', url, { token: OPERATOR_TOKEN })).text)
    for (const url of playerUrls) texts.push((await server.api('GET', url, { token })).text)
    texts.push(...client.messages.map((m) => JSON.stringify(m)))
    for (const text of texts) expect(text).not.toContain(active.seed)
    // The audit of a drop under the active seed still checks it, without showing it.
    const audit = await server.api('GET', `/api/audit/drops/${ids[0]}`, { token: OPERATOR_TOKEN })
    expect(audit.body.drop.serverSeed).toBeNull()
    // Once rotated, it is revealed (to both).
    const rotated = await server.api('POST', '/api/seeds/rotate', { token })
    expect(rotated.body.previousServerSeed).toBe(active.seed)
    expect((await server.api('GET', `/api/audit/drops/${ids[0]}`, { token: OPERATOR_TOKEN })).body.drop.serverSeed).toBe(active.seed)
  })
})

describe('slow and vanished clients', () => {
  it('skips snapshots to a client that stops reading, then closes it (1013), keeping its send queue bounded', async () => {
    const SOFT = 16 * 1024
    const HARD = 256 * 1024
    const server = await serverWith({ SNAPSHOT_HZ: '60', WS_SOFT_BUFFER: String(SOFT), WS_HARD_BUFFER: String(HARD), DROP_RATE: '2000', DROP_BURST: '2000', MAX_BALLS_PER_ROOM: '4096', WS_MESSAGE_RATE: '100000', WS_MESSAGE_BURST: '100000' })
    const slow = await server.player('16-high')
    const slowConnection = [...server.arena.connections].find((c) => c.account.playerId === slow.session.playerId)
    slow.client.socket._socket.pause()
    const pumps = []
    for (let i = 0; i < 3; i++) pumps.push(await server.player('16-high'))
    let maxQueued = 0
    const deadline = Date.now() + 45_000
    while (!slowConnection.closed && Date.now() < deadline) {
      for (const { client } of pumps) for (let i = 0; i < 20; i++) client.send({ type: 'drop', bet: 1 })
      await new Promise((resolve) => setTimeout(resolve, 25))
      if (!slowConnection.closed) maxQueued = Math.max(maxQueued, slowConnection.socket.bufferedAmount)
    }
    expect(slowConnection.closed).toBe(true)
    const metrics = await server.api('GET', '/metrics', { token: OPERATOR_TOKEN })
    expect(Number(/plinko_snapshots_skipped_total (\d+)/.exec(metrics.text)[1])).toBeGreaterThan(0)
    expect(Number(/plinko_ws_slow_consumers_closed_total (\d+)/.exec(metrics.text)[1])).toBeGreaterThanOrEqual(1)
    // Never much more than the hard limit (at most what one tick sends on top: a snapshot and its events).
    expect(maxQueued).toBeLessThanOrEqual(2 * HARD)
    console.info(`[slow-consumer] closed with the queue at most ${maxQueued} bytes (hard limit ${HARD})`)
    // The others are unaffected.
    for (const { client } of pumps) { await client.sync(); expect(client.closeEvent).toBeNull() }
    slow.client.socket._socket.resume()
    expect([1013, 1006]).toContain((await slow.client.closed).code)
  })

  it('records the payout of a client that vanishes mid-drop, and shows it on reconnect', async () => {
    const server = await serverWith({})
    const { session, client, token } = await server.player('16-high')
    for (const bet of [10, 20, 30, 40, 50]) client.send({ type: 'drop', bet })
    for (let i = 0; i < 5; i++) await client.take('dropped')
    expect(client.messages.some((m) => m.type === 'settled')).toBe(false)
    client.socket.terminate() // no close frame: the peer just disappears
    const rows = await eventually(async () => {
      const found = await backend.query(server.database.database, "SELECT id, payout FROM drops WHERE player_id = $1 AND status = 'settled'", [session.playerId])
      return found.length === 5 && found
    })
    const expected = (100000 - 150) * 1000 + rows.reduce((sum, r) => sum + Number(r.payout), 0) // milli-credits
    // Committed (another connection sees the rows) comes just before the process applies the commit: wait for that too.
    await eventually(() => server.arena.unsettledDrops === 0)
    const again = await server.connect(token)
    expect(Math.round(again.welcome.balance * 1000)).toBe(expected)
    const history = await server.api('GET', '/api/drops', { token })
    expect(history.body.drops.map((d) => d.status)).toEqual(Array(5).fill('settled'))
    await expectConsistentLedger(expect, backend, server.database.database, { playerIds: [session.playerId], startingBalance: 100000 })
    await again.close()
    // Nothing of the player is left in memory once its last connection is gone.
    await eventually(() => !server.arena.accounts.accounts.has(session.playerId))
  })
})
