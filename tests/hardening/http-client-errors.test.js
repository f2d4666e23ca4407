import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import net from 'node:net'
import { Writable } from 'node:stream'
import { buildApp } from '../../server/app.js'
import { loadConfig } from '../../server/config.js'

/**
 * Requests that never reach a route (issue #14, items 7 and 8): each gets
 * `{ code, message }` like every other error, and a client sending garbage
 * does not fill the logs.
 */
let app
let port
let token
const logLines = []

beforeAll(async () => {
  const config = loadConfig({
    DATABASE_URL: 'sqlite::memory:', OPERATOR_TOKEN: 'operator-token-for-tests-0123456789', CLIENT_DIR: '/nonexistent/plinko-client',
    HTTP_REQUEST_TIMEOUT_MS: '1000', HTTP_RATE_LIMIT: '1000000', SESSION_RATE_LIMIT: '1000000'
  })
  const stream = new Writable({ write (chunk, encoding, done) { logLines.push(...chunk.toString().split('\n').filter(Boolean)); done() } })
  app = await buildApp(config, { logger: { level: 'info', stream } })
  await app.listen({ port: 0, host: '127.0.0.1' })
  port = app.server.address().port
  token = (await app.inject({ method: 'POST', url: '/api/session' })).json().token
})
afterAll(async () => { await app?.close() })

/** Raw bytes to the server; the whole reply once the server closes (or after `ms`). */
function raw (bytes, { ms = 5000 } = {}) {
  return new Promise((resolve) => {
    const socket = net.connect(port, '127.0.0.1')
    let reply = ''
    const timer = setTimeout(() => socket.destroy(), ms)
    socket.on('data', (chunk) => { reply += chunk })
    socket.on('error', () => {})
    socket.on('close', () => { clearTimeout(timer); resolve(parse(reply)) })
    socket.write(bytes)
  })
}

function parse (reply) {
  const head = reply.slice(0, reply.indexOf('\r\n\r\n'))
  const body = reply.slice(reply.indexOf('\r\n\r\n') + 4)
  let json = null
  try { json = JSON.parse(body) } catch {}
  return { status: Number(/^HTTP\/1\.1 (\d{3})/.exec(head)?.[1]), head, json }
}

describe('HTTP errors below the routes', () => {
  it('answers each with its status and a named code', async () => {
    const cases = [
      [`GET /api/health HTTP/1.1\r\nHost: x\r\nX-Big: ${'a'.repeat(70_000)}\r\n\r\n`, 431, 'E_HEADERS_TOO_LARGE'],
      ['GET /api/health HTTP/1.1\r\nHost: x\r\n', 408, 'E_TIMEOUT'], // a slow sender: the head never ends
      ['GET /api/health HTTP/1.1\r\n\r\n', 400, 'E_BAD_REQUEST'], // no Host
      ['GARBAGE\r\n\r\n', 400, 'E_BAD_REQUEST'],
      ['POST /api/session HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\nabc\r\n', 400, 'E_BAD_REQUEST'],
      ['GET /api/health HTTP/1.1\r\nHost: x\r\nContent-Length: -1\r\n\r\n', 400, 'E_BAD_REQUEST'],
      [`PUT /api/seeds/client HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer TOKEN\r\nContent-Type: application/json\r\nContent-Length: 3\r\nConnection: close\r\n\r\n{"a`, 400, 'E_BAD_REQUEST'],
      ['PUT /api/seeds/client HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer TOKEN\r\nContent-Type: text/xml\r\nContent-Length: 3\r\nConnection: close\r\n\r\nabc', 415, 'E_UNSUPPORTED_MEDIA_TYPE'],
      [`PUT /api/seeds/client HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer TOKEN\r\nContent-Type: application/json\r\nContent-Length: 20000\r\nConnection: close\r\n\r\n${'x'.repeat(20000)}`, 413, 'E_PAYLOAD_TOO_LARGE']
    ]
    for (const [text, status, code] of cases) {
      const reply = await raw(Buffer.from(text.replaceAll('TOKEN', token), 'latin1'))
      const label = JSON.stringify(text.slice(0, 60))
      expect(reply.status, label).toBe(status)
      expect(reply.json, label).toMatchObject({ code })
      expect(typeof reply.json.message, label).toBe('string')
    }
  })

  it('logs a flood of malformed chunked bodies at no level above debug, and keeps serving', async () => {
    const before = logLines.length
    await Promise.all(Array.from({ length: 200 }, () => raw(Buffer.from('POST /api/session HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n{"x"', 'latin1'))))
    const logged = logLines.slice(before).map((line) => JSON.parse(line))
    expect(logged.filter((entry) => entry.level >= 40), JSON.stringify(logged.find((entry) => entry.level >= 40))).toEqual([])
    expect(logLines.slice(before).join('\n')).not.toMatch(/TypeError|stack/)
    const health = await fetch(`http://127.0.0.1:${port}/api/health`)
    expect(health.status).toBe(200)
  })
})
