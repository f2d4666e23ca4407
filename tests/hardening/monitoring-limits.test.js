import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer } from '../server/helpers/server.js'

/**
 * Issue #21, item 6: /metrics (766/s) and /api/health (7,369/s) were exempt
 * from every limit, and one client held the core. Each now has a budget of
 * its own per address (MONITORING_RATE_LIMIT a minute).
 */
describe('/metrics and /api/health are rate-limited per address, each on its own budget', () => {
  const backend = storeBackend('sqlite')
  let server
  beforeAll(async () => {
    await backend.setup()
    server = await startServer(await backend.newDatabase(), { env: { MONITORING_RATE_LIMIT: '5', HTTP_RATE_LIMIT: '3' } })
  })
  afterAll(async () => {
    await server?.close()
    await backend.teardown()
  })

  const get = (url, ip) => server.app.inject({ method: 'GET', url, remoteAddress: ip })

  for (const url of ['/metrics', '/api/health']) {
    it(`${url}: 5 a minute, then 429 E_RATE_LIMITED with Retry-After; another address is not affected`, async () => {
      const ip = url === '/metrics' ? '10.3.0.1' : '10.3.0.2'
      for (let i = 0; i < 5; i++) expect((await get(url, ip)).statusCode, `request ${i + 1}`).toBe(200)
      const limited = await get(url, ip)
      expect(limited.statusCode).toBe(429)
      expect(limited.json()).toMatchObject({ code: 'E_RATE_LIMITED' })
      expect(Number(limited.headers['retry-after'])).toBeGreaterThan(0)
      expect((await get(url, '10.3.0.9')).statusCode).toBe(200)
    })
  }

  it('keeps the budgets apart: API requests do not use up the probes\', nor the reverse', async () => {
    const ip = '10.3.0.3'
    for (let i = 0; i < 3; i++) expect((await get('/api/rooms', ip)).statusCode).toBe(200)
    expect((await get('/api/rooms', ip)).statusCode).toBe(429)
    expect((await get('/api/health', ip)).statusCode).toBe(200)
    expect((await get('/metrics', ip)).statusCode).toBe(200)
  })
})
