import { describe, it, expect, afterEach } from 'vitest'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer } from '../server/helpers/server.js'

/**
 * Issue #21, item 6: a client flooding /api/health or /metrics on the
 * public port cost the game CPU even when answered 429. MONITORING_PORT
 * serves them on a listener of their own (loopback by default); the public
 * port then answers them only with MONITORING_ON_PUBLIC_PORT=true.
 */
describe('MONITORING_PORT: /api/health and /metrics on a listener of their own', () => {
  const backend = storeBackend('sqlite')
  let server
  afterEach(async () => {
    await server?.close()
    server = null
    await backend.teardown()
  })

  async function serverWith (env, logStream) {
    await backend.setup()
    server = await startServer(await backend.newDatabase(), { env, logStream })
    return server
  }
  const publicUrl = () => `http://127.0.0.1:${server.app.server.address().port}`
  const monitoringUrl = () => `http://127.0.0.1:${server.app.monitoring.server.address().port}`

  it('serves them on MONITORING_HOST:MONITORING_PORT (no rate limit there), and not on the public port', async () => {
    await serverWith({ MONITORING_PORT: '0', MONITORING_RATE_LIMIT: '2' })
    expect(server.app.monitoring.server.address().address).toBe('127.0.0.1')
    for (let i = 0; i < 4; i++) {
      const health = await fetch(`${monitoringUrl()}/api/health`)
      expect(health.status).toBe(200)
      expect(await health.json()).toMatchObject({ status: 'ok' })
    }
    const metrics = await fetch(`${monitoringUrl()}/metrics`)
    expect(metrics.status).toBe(200)
    expect(await metrics.text()).toMatch(/plinko_ticks_total/)
    for (const path of ['/api/health', '/metrics']) {
      const response = await fetch(publicUrl() + path)
      expect(response.status).toBe(404)
      expect(await response.json()).toMatchObject({ code: 'E_NOT_FOUND' })
    }
    // The game is on the public port only.
    expect((await fetch(`${publicUrl()}/api/rooms`)).status).toBe(200)
    expect((await fetch(`${monitoringUrl()}/api/rooms`)).status).toBe(404)
  })

  it('answers them on both with MONITORING_ON_PUBLIC_PORT=true, and on the public port alone when MONITORING_PORT is unset', async () => {
    await serverWith({ MONITORING_PORT: '0', MONITORING_ON_PUBLIC_PORT: 'true' })
    for (const url of [publicUrl(), monitoringUrl()]) {
      expect((await fetch(`${url}/api/health`)).status).toBe(200)
      expect((await fetch(`${url}/metrics`)).status).toBe(200)
    }
    await server.close()
    await backend.teardown()
    await serverWith({})
    expect(server.app.monitoring).toBeUndefined()
    expect((await fetch(`${publicUrl()}/api/health`)).status).toBe(200)
  })

  it('logs no line per probe or scrape there, while the public port logs its requests', async () => {
    const lines = []
    await serverWith({ MONITORING_PORT: '0' }, { write: (line) => { lines.push(JSON.parse(line)) } })
    const requestLines = (listener) => lines.filter((line) => line.req !== undefined && line.listener === listener)
    for (let i = 0; i < 3; i++) expect((await fetch(`${monitoringUrl()}/api/health`)).status).toBe(200)
    expect((await fetch(`${monitoringUrl()}/metrics`)).status).toBe(200)
    expect((await fetch(`${publicUrl()}/api/rooms`)).status).toBe(200)
    expect(lines.some((line) => line.req?.url === '/api/rooms' && line.listener === undefined)).toBe(true)
    expect(requestLines('monitoring')).toEqual([])
  })
})
