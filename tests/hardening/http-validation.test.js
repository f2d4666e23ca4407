import { describe, it, expect, beforeAll } from 'vitest'
import { STORE_KINDS } from '../server/helpers/stores.js'
import { useServerOn, OPERATOR_TOKEN } from '../server/helpers/server.js'

/**
 * What an attack pass found in request validation (issue #14, items 1, 9, 10):
 * numbers in exponent form and Infinity passed the integer checks, schema
 * checks ran before the operator check, and the HTTP body coerced what the
 * WebSocket refuses.
 */
describe.each(STORE_KINDS)('request validation on %s', (kind) => {
  const context = useServerOn(kind)
  let server
  let alice
  beforeAll(async () => {
    server = context.server
    alice = await server.player('8-low')
  })

  const seeds = 'serverSeed=a&clientSeed=b'
  const numeric = [
    ['player', '/api/drops?limit=V'], ['player', '/api/drops?before=V'], ['player', '/api/drops/V'],
    ['operator', '/api/audit/drops?limit=V'], ['operator', '/api/audit/drops?before=V'], ['operator', '/api/audit/drops/V'],
    ['operator', `/api/audit/verify?${seeds}&nonce=V`], ['operator', `/api/audit/verify?${seeds}&nonce=0&rows=V`]
  ]

  it('refuses every numeric parameter that is not a finite safe integer in range with 400 E_BAD_REQUEST', async () => {
    // 0x10, 0o20 and 0b10000 are 16 to Number(), and were taken as 16 (issue #21, item 8).
    for (const value of ['1e400', '-1e400', 'Infinity', '-Infinity', '1e16', '9007199254740992', '-9007199254740992', '1.5', '2e-1', 'NaN', '', 'x', '0x10', '0X10', '0o20', '0b10000', ' 0x10 ']) {
      for (const [who, url] of numeric) {
        const token = who === 'player' ? alice.token : OPERATOR_TOKEN
        const response = await server.api('GET', url.replace('V', value), { token })
        const label = `${url.replace('V', value)} → ${response.status} ${response.text.slice(0, 120)}`
        expect(response.status, label).toBe(400)
        expect(response.body.code, label).toBe('E_BAD_REQUEST')
      }
    }
    // A whole number in exponent form within range is that number.
    const hundred = await server.api('GET', '/api/drops?limit=1e2', { token: alice.token })
    expect(hundred.status).toBe(200)
    const verified = await server.api('GET', `/api/audit/verify?${seeds}&nonce=1e1&rows=1.2e1`, { token: OPERATOR_TOKEN })
    expect(verified.status).toBe(200)
    expect(verified.body.engineVersion).toBeDefined()
  })

  it('takes a time filter only as ISO 8601 or epoch milliseconds (from=1.5 was some day in 2001)', async () => {
    for (const value of ['1.5', '1.', '-1', 'Dec 2 2026', '2 December 2026', '2026/12/02', '12-02-2026', '2026-12-02 10:00', 'Wed, 02 Dec 2026 05:00:00 GMT', '0x10']) {
      for (const name of ['from', 'to']) {
        const response = await server.api('GET', `/api/audit/drops?${name}=${encodeURIComponent(value)}`, { token: OPERATOR_TOKEN })
        expect(response.status, `${name}=${value}`).toBe(400)
        expect(response.body, `${name}=${value}`).toEqual({ code: 'E_BAD_REQUEST', message: `${name} must be an ISO 8601 time or milliseconds since the epoch` })
      }
    }
    for (const value of ['0', '1767225600000', '2026-01-01', '2026-01-01T00:00Z', '2026-01-01T00:00:00.123+02:00', '2026-01-01T00:00:00']) {
      const response = await server.api('GET', `/api/audit/drops?from=${encodeURIComponent(value)}`, { token: OPERATOR_TOKEN })
      expect(response.status, value).toBe(200)
    }
  })

  it('checks the operator token before it looks at the query (401 before any schema error)', async () => {
    for (const url of ['/api/audit/drops?zzz=1', '/api/audit/drops?limit=1e400', '/api/audit/verify', '/api/audit/export?format=xml', '/api/audit/rooms/9-nope/stats?zzz=1', '/api/audit/drops/abc']) {
      const missing = await server.api('GET', url)
      expect(missing.status, url).toBe(401)
      expect(missing.body.code, url).toBe('E_UNAUTHORIZED')
      expect(missing.body.message, url).not.toMatch(/querystring|params|must/)
      const wrong = await server.api('GET', url, { token: alice.token })
      expect(wrong.status, url).toBe(403)
      expect(wrong.body.code, url).toBe('E_FORBIDDEN')
    }
    // Player routes too: no session, no schema talk.
    for (const url of ['/api/drops?zzz=1', '/api/drops/abc', '/api/seeds?x=1']) {
      const missing = await server.api('GET', url)
      expect(missing.status, url).toBe(401)
      expect(missing.body.code, url).toBe('E_UNAUTHORIZED')
    }
  })

  it('refuses a client seed of the wrong type over HTTP as the WebSocket does (E_BAD_SEED, no coercion)', async () => {
    const before = (await server.api('GET', '/api/me', { token: alice.token })).body.clientSeed
    for (const clientSeed of [123, true, ['abc'], { a: 1 }, null, 1.5]) {
      const response = await server.api('PUT', '/api/seeds/client', { token: alice.token, body: { clientSeed } })
      expect(response.status, JSON.stringify(clientSeed)).toBe(400)
      expect(response.body.code, JSON.stringify(clientSeed)).toBe('E_BAD_SEED')
    }
    expect((await server.api('GET', '/api/me', { token: alice.token })).body.clientSeed).toBe(before)
    // The WebSocket says the same of the same seeds.
    for (const clientSeed of [123, true, ['abc']]) {
      alice.client.send({ type: 'drop', bet: 1, clientSeed })
      const error = await alice.client.take('error')
      expect(error.code).toMatch(/^E_BAD_(SEED|MESSAGE)$/)
    }
    const ok = await server.api('PUT', '/api/seeds/client', { token: alice.token, body: { clientSeed: 'fine-seed' } })
    expect(ok.status).toBe(200)
    expect(ok.body.clientSeed).toBe('fine-seed')
  })
})
