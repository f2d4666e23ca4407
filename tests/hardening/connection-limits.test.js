import { describe, it, expect, afterEach } from 'vitest'
import net from 'node:net'
import WebSocket from 'ws'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer } from '../server/helpers/server.js'
import { connectionCeiling } from '../../server/limits/connection-limits.js'

/**
 * Issue #21, item 4: no cap on HTTP connections, per address or in total:
 * two slowloris runs of 11,000 connections took a server to its 20,000
 * descriptor limit, and honest /api/health probes failed for 30 s.
 */
const backend = storeBackend('sqlite')
let server
afterEach(async () => {
  await server?.close()
  server = null
  await backend.teardown()
})

async function serverWith (env) {
  await backend.setup()
  server = await startServer(await backend.newDatabase(), { env })
  return server
}

/** A raw TCP connection; `closed` resolves with what the server sent before closing. */
function rawSocket (port) {
  const socket = net.connect(port, '127.0.0.1')
  let received = ''
  socket.on('data', (chunk) => { received += chunk })
  socket.on('error', () => {})
  const opened = new Promise((resolve) => socket.once('connect', resolve))
  const closed = new Promise((resolve) => socket.once('close', () => resolve(received)))
  return { socket, opened, closed }
}

async function get (port, path) {
  const response = await fetch(`http://127.0.0.1:${port}${path}`)
  return { status: response.status, body: await response.json() }
}

/** Counter sample from /metrics. */
async function sample (name, reason) {
  const text = (await server.app.inject({ method: 'GET', url: '/metrics' })).body
  const match = new RegExp(`^${name}\\{reason="${reason}"\\} (\\d+)$`, 'm').exec(text)
  return match ? Number(match[1]) : 0
}

describe('HTTP connection caps', () => {
  it('at the per-address cap, sheds that address\'s longest-idle connection for a new one', async () => {
    const { port } = await serverWith({ HTTP_MAX_CONNECTIONS_PER_IP: '5' })
    const idle = []
    for (let i = 0; i < 5; i++) {
      const socket = rawSocket(port)
      await socket.opened
      idle.push(socket)
    }
    // A slow sender among them: half a request's headers.
    idle[4].socket.write('GET /api/health HTTP/1.1\r\nHost: x\r\n')
    const probe = await get(port, '/api/health')
    expect(probe.status).toBe(200)
    expect(await idle[0].closed).toBe('')
    expect(idle.slice(1).every((s) => !s.socket.destroyed)).toBe(true)
    expect(await sample('plinko_http_connections_shed_total', 'per_address')).toBeGreaterThanOrEqual(1)
    for (const s of idle) s.socket.destroy()
  })

  it('refuses a new connection with 429 E_TOO_MANY_CONNECTIONS when none from its address is idle (WebSockets are never shed)', async () => {
    const { port } = await serverWith({ HTTP_MAX_CONNECTIONS_PER_IP: '3' })
    const session = await server.session()
    const sockets = []
    for (let i = 0; i < 3; i++) {
      const ws = new WebSocket(server.wsUrl(session.token))
      await new Promise((resolve, reject) => { ws.once('message', resolve); ws.once('error', reject) })
      sockets.push(ws)
    }
    const refused = rawSocket(port)
    await refused.opened
    const reply = await refused.closed
    expect(reply).toMatch(/^HTTP\/1\.1 429 Too Many Requests\r\n/)
    expect(reply).toMatch(/Retry-After: 1\r\n/)
    expect(JSON.parse(reply.slice(reply.indexOf('\r\n\r\n') + 4))).toMatchObject({ code: 'E_TOO_MANY_CONNECTIONS' })
    expect(sockets.every((ws) => ws.readyState === WebSocket.OPEN)).toBe(true)
    expect(await sample('plinko_http_connections_refused_total', 'per_address')).toBe(1)
    for (const ws of sockets) ws.close()
  })

  it('applies the total cap across addresses, shedding the longest idle first', async () => {
    const { port } = await serverWith({ HTTP_MAX_CONNECTIONS: '4' })
    const idle = []
    for (let i = 0; i < 4; i++) {
      const socket = rawSocket(port)
      await socket.opened
      idle.push(socket)
    }
    expect((await get(port, '/api/health')).status).toBe(200)
    expect(await idle[0].closed).toBe('')
    expect(await sample('plinko_http_connections_shed_total', 'total')).toBeGreaterThanOrEqual(1)
    for (const s of idle) s.socket.destroy()
  })

  it('never holds more than 90% of the open-file limit, whatever HTTP_MAX_CONNECTIONS says', () => {
    expect(connectionCeiling(0, 20_000)).toBe(18_000)
    expect(connectionCeiling(50_000, 20_000)).toBe(18_000)
    expect(connectionCeiling(100, 20_000)).toBe(100)
    expect(connectionCeiling(0, 1024)).toBe(921)
  })

  it('closes slow headers after HTTP_HEADERS_TIMEOUT_MS (408), and a connection that sends nothing too, well before the 30 s request timeout', async () => {
    const { port } = await serverWith({ HTTP_HEADERS_TIMEOUT_MS: '1000' })
    expect(server.config.httpRequestTimeoutMs).toBe(30_000)
    const started = Date.now()
    const slow = rawSocket(port)
    await slow.opened
    slow.socket.write('GET /api/health HTTP/1.1\r\nHost: x\r\n')
    const silent = rawSocket(port)
    await silent.opened
    const [slowReply, silentReply] = await Promise.all([slow.closed, silent.closed])
    expect(slowReply).toMatch(/^HTTP\/1\.1 408 /)
    expect(slowReply).toContain('"code":"E_TIMEOUT"')
    expect(silentReply).toMatch(/^HTTP\/1\.1 408 /)
    expect(Date.now() - started).toBeLessThan(30_000)
  })
})
