import { describe, it, expect, beforeAll } from 'vitest'
import fc from 'fast-check'
import net from 'node:net'
import { ERROR_CODES } from '../../server/errors.js'
import { STORE_KINDS } from '../server/helpers/stores.js'
import { useServerOn, OPERATOR_TOKEN } from '../server/helpers/server.js'
import { ledgerTotals } from './helpers/ledger.js'

/**
 * Fuzzes every HTTP route (methods, paths, query strings, bodies, headers)
 * through fastify's inject and, for what inject cannot express, raw bytes
 * on a real socket. Never a 5xx; every 4xx carries a named code; refused
 * requests change no balance and write no drop.
 */
const SEED = Number(process.env.PLINKO_FUZZ_SEED ?? 20261123)
const REQUESTS = 3000
const ROUTES = [
  '/api/session', '/api/me', '/api/drops', '/api/drops/1', '/api/drops/:id', '/api/seeds', '/api/seeds/rotate', '/api/seeds/client',
  '/api/rooms', '/api/health', '/metrics', '/api/audit/drops', '/api/audit/drops/1', '/api/audit/verify', '/api/audit/export',
  '/api/audit/rooms/8-low/stats', '/api/audit/rooms/:id/stats', '/api/audit/token-check', '/engine/index.js', '/engine/:file', '/vendor/seedrandom.js', '/ws', '/', '/audit'
]
const QUERY_KEYS = ['limit', 'before', 'player', 'room', 'from', 'to', 'serverSeed', 'clientSeed', 'nonce', 'rows', 'risk', 'serverSeedHash', 'format', 'token', 'x', '__proto__', 'constructor']
const value = fc.oneof(
  fc.constantFrom('', '0', '-1', '1', '1.5', 'NaN', 'Infinity', '1e400', '1e300', '9007199254740993', '99999999999999999999', 'true', 'null', '[]', '{}', 'a'.repeat(300),
    '8-low', '17-low', 'json', 'ndjson', 'xml', 'medium', 'extreme', '2020-01-01', 'yesterday', '0'.repeat(64), 'g'.repeat(64), '%00', '%ff', '%', '%E0%A4%A', '\u0000', '..%2f..%2fetc%2fpasswd'),
  fc.string({ maxLength: 40 }).map(encodeURIComponent),
  fc.integer().map(String),
  fc.double().map(String)
)
const query = fc.array(fc.tuple(fc.constantFrom(...QUERY_KEYS), value), { maxLength: 5 }).map((pairs) => pairs.length ? '?' + pairs.map(([k, v]) => `${k}=${v}`).join('&') : '')
const segment = fc.oneof(value, fc.constantFrom('..', '.', '%2e%2e', '8-low', 'x.js', 'index.js', '../server/config.js', '%2e%2e%2fpackage.json'))
const pathArb = fc.oneof(
  { weight: 6, arbitrary: fc.constantFrom(...ROUTES) },
  { weight: 3, arbitrary: fc.tuple(fc.constantFrom(...ROUTES), segment).map(([route, s]) => route.replace(/:(id|file)/, s)) },
  { weight: 1, arbitrary: fc.array(segment, { minLength: 1, maxLength: 4 }).map((parts) => '/' + parts.join('/')) },
  { weight: 1, arbitrary: fc.constantFrom(...ROUTES).map((r) => r + '/') },
  { weight: 1, arbitrary: fc.constantFrom(...ROUTES).map((r) => r.toUpperCase()) }
)
const body = fc.oneof(
  fc.constant(undefined),
  fc.jsonValue({ maxDepth: 3 }).map((v) => JSON.stringify(v)),
  fc.record({ clientSeed: fc.oneof(fc.string({ maxLength: 80 }), fc.jsonValue()) }, { requiredKeys: [] }).map((v) => JSON.stringify(v)),
  fc.string({ maxLength: 100 }),
  fc.constantFrom('{"clientSeed":', '{"clientSeed":"ok","__proto__":{"x":1}}', '{"constructor":{"prototype":{"x":1}}}', 'x'.repeat(20_000), JSON.stringify({ clientSeed: 'x'.repeat(20_000) }))
)

/** Edges of every typed parameter, each with player and operator credentials. */
const EDGES = ['0', '-1', '1.5', '1e300', '1e400', '-1e400', 'Infinity', '-Infinity', '1e2', '0x10', '9007199254740991', '9007199254740992', '99999999999999999999', '-9223372036854775809', 'NaN', '%00', '%ff', '']
const EDGE_URLS = EDGES.flatMap((v) => [
  `/api/drops?before=${v}`, `/api/drops?limit=${v}`, `/api/drops/${v}`, `/api/audit/drops/${v}`, `/api/audit/drops?before=${v}`, `/api/audit/drops?limit=${v}`,
  `/api/audit/drops?from=${v}&to=${v}`, `/api/audit/drops?player=${v}&room=${v}`, `/api/audit/verify?serverSeed=a&clientSeed=b&nonce=${v}`,
  `/api/audit/verify?serverSeed=${v}&clientSeed=${v}&nonce=0&rows=${v}`, `/api/audit/verify?serverSeed=a&clientSeed=${v}&nonce=1`,
  `/api/audit/export?player=${v}`, `/api/audit/export?serverSeedHash=${v}`, `/api/audit/rooms/${v}/stats`, `/engine/${v}`
])

describe.each(STORE_KINDS)('HTTP fuzz on %s', (kind) => {
  const context = useServerOn(kind)
  const backend = context.backend
  let server
  let database
  beforeAll(() => { ({ server, database } = context) })

  it(`answers ${REQUESTS} random requests with 2xx/3xx or a named 4xx, never a 5xx`, async () => {
    const alice = await server.player('8-low')
    alice.client.send({ type: 'drop', bet: 10 })
    await alice.client.take('settled')
    const tokens = [undefined, alice.token, OPERATOR_TOKEN, 'f'.repeat(64), 'x', '', 'a'.repeat(10_000)]
    const request = fc.record({
      method: fc.constantFrom('GET', 'GET', 'GET', 'POST', 'PUT', 'DELETE', 'PATCH', 'OPTIONS', 'HEAD', 'TRACE'),
      path: pathArb,
      query,
      body,
      token: fc.constantFrom(...tokens),
      scheme: fc.constantFrom('Bearer ', 'bearer ', 'Basic ', 'Bearer', ''),
      contentType: fc.constantFrom(undefined, 'application/json', 'text/plain', 'application/x-www-form-urlencoded', 'multipart/form-data; boundary=x', 'application/json; charset=latin1', 'garbage'),
      ip: fc.constantFrom('127.0.0.1', '10.0.0.1', '::1')
    })
    const before = await ledgerTotals(backend, database.database)
    const statuses = new Map()
    const edges = EDGE_URLS.flatMap((path) => [alice.token, OPERATOR_TOKEN].map((token) => ({ method: 'GET', path, query: '', token, scheme: 'Bearer ', ip: '127.0.0.1' })))
    for (const r of [...edges, ...fc.sample(request, { seed: SEED, numRuns: REQUESTS })]) {
      const headers = {}
      if (r.token !== undefined) headers.authorization = r.scheme + r.token
      if (r.contentType) headers['content-type'] = r.contentType
      const response = await server.app.inject({ method: r.method, url: r.path + r.query, headers, payload: r.method === 'GET' || r.method === 'HEAD' ? undefined : r.body, remoteAddress: r.ip })
      const label = `${r.method} ${r.path}${r.query} → ${response.statusCode} ${response.body.slice(0, 200)}`
      statuses.set(response.statusCode, (statuses.get(response.statusCode) ?? 0) + 1)
      expect(response.statusCode, label).toBeLessThan(500)
      if (response.statusCode >= 400 && r.method !== 'HEAD') {
        let json
        try { json = response.json() } catch { throw new Error(`not JSON: ${label}`) }
        expect(ERROR_CODES[json.code], label).toBeDefined()
        expect(typeof json.message, label).toBe('string')
      }
    }
    // Rotations, client seeds and sessions may succeed; no drop is written and no balance moves.
    expect(await ledgerTotals(backend, database.database)).toEqual(before)
    expect([...statuses.keys()].some((s) => s >= 400)).toBe(true)
    expect([...statuses.keys()].some((s) => s < 300)).toBe(true)
    await alice.client.close()
  })

  /** Raw bytes to the listening port; resolves with the status line of the reply (or '' if it just closed). */
  function raw (bytes) {
    return new Promise((resolve) => {
      const socket = net.connect(server.port, '127.0.0.1')
      let reply = ''
      socket.on('data', (chunk) => { reply += chunk })
      socket.on('error', () => {})
      socket.on('close', () => resolve(reply.split('\r\n')[0]))
      socket.end(bytes)
    })
  }

  it('answers malformed HTTP on a real socket with a 4xx (or a plain close), and keeps serving', async () => {
    const cases = [
      'GARBAGE\r\n\r\n',
      'GET / HTTP/9.9\r\nHost: x\r\n\r\n',
      'GET /api/health HTTP/1.1\r\nHost: x\r\nContent-Length: -1\r\n\r\n',
      'GET /api/health HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\nContent-Length: 5\r\n\r\n0\r\n\r\n',
      `GET /api/health HTTP/1.1\r\nHost: x\r\nX-Big: ${'a'.repeat(70_000)}\r\n\r\n`,
      'GET /api/health HTTP/1.1\r\nHost: x\r\nBad Header\r\n\r\n',
      'GET /api/health HTTP/1.1\r\nHost: x\r\nX: \u0000\u0001\r\n\r\n',
      'PUT /api/seeds/client HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 100000\r\n\r\n{"clientSeed":"',
      'GET /ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 99\r\nSec-WebSocket-Key: nope\r\n\r\n',
      'GET /ws?token=%zz HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n'
    ]
    for (const text of cases) {
      const status = await raw(Buffer.from(text, 'latin1'))
      if (status !== '') expect(status, JSON.stringify(text.slice(0, 80))).toMatch(/^HTTP\/1\.1 (4\d\d|101)/)
    }
    const health = await fetch(`http://127.0.0.1:${server.port}/api/health`)
    expect(health.status).toBe(200)
  })
})
