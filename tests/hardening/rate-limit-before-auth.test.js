import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer } from '../server/helpers/server.js'

/**
 * Issue #21 (c): the token checks ran before HTTP_RATE_LIMIT's, so a
 * request with no token at all (401, which is no guess: not counted as a
 * failed authentication) was not counted either: unlimited 401s. The rate
 * limit now runs first on every route.
 */
describe('HTTP_RATE_LIMIT counts requests before their token is checked', () => {
  const backend = storeBackend('sqlite')
  let server
  beforeAll(async () => {
    await backend.setup()
    server = await startServer(await backend.newDatabase(), { env: { HTTP_RATE_LIMIT: '5' } })
  })
  afterAll(async () => {
    await server?.close()
    await backend.teardown()
  })

  const statuses = async (url, ip, count, headers = {}) => {
    const codes = []
    for (let i = 0; i < count; i++) codes.push((await server.app.inject({ method: 'GET', url, remoteAddress: ip, headers })).statusCode)
    return codes
  }

  it('player routes: 5 × 401 without a token, then 429; another address is not affected', async () => {
    expect(await statuses('/api/me', '10.4.0.1', 8)).toEqual([401, 401, 401, 401, 401, 429, 429, 429])
    expect(await statuses('/api/me', '10.4.0.9', 1)).toEqual([401])
  })

  it('operator routes: 5 × 401 without a token, then 429 (a right token from there waits too)', async () => {
    expect(await statuses('/api/audit/drops', '10.4.0.2', 8)).toEqual([401, 401, 401, 401, 401, 429, 429, 429])
    const limited = await server.app.inject({ method: 'GET', url: '/api/audit/drops', remoteAddress: '10.4.0.2', headers: { authorization: `Bearer ${server.config.operatorToken}` } })
    expect(limited.statusCode).toBe(429)
    expect(limited.json()).toMatchObject({ code: 'E_RATE_LIMITED' })
  })
})
