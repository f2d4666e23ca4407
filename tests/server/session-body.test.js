import { describe, it, expect } from 'vitest'
import { useServerOn } from './helpers/server.js'

/**
 * POST /api/session takes no options. What the clients send (no body: the
 * player page's apiRequest, k6's http.post(url, null), the scripts' fetch)
 * and an explicit `{}` create a guest; anything else is 400 E_BAD_REQUEST
 * and creates no player.
 */
describe('POST /api/session body', () => {
  const context = useServerOn('sqlite')

  async function playerCount () {
    const [row] = await context.backend.query(context.database.database, 'SELECT COUNT(*) AS n FROM players')
    return Number(row.n)
  }

  async function post (payload, contentType) {
    const headers = contentType ? { 'content-type': contentType } : {}
    const response = await context.server.app.inject({ method: 'POST', url: '/api/session', payload, headers })
    return { status: response.statusCode, body: response.json() }
  }

  it('creates a guest with no body, as every current client sends it, and with {}', async () => {
    const before = await playerCount()
    for (const response of [await post(undefined), await post({}), await post('{}', 'application/json')]) {
      expect(response.status).toBe(201)
      expect(response.body).toEqual({
        token: expect.any(String),
        playerId: expect.any(String),
        balance: expect.any(Number),
        serverSeedHash: expect.stringMatching(/^[0-9a-f]{64}$/),
        clientSeed: expect.any(String),
        nonce: 0
      })
    }
    expect(await playerCount()).toBe(before + 3)
  })

  it('creates a guest from a real HTTP client that sends no body (fetch, as the page and scripts do)', async () => {
    const response = await fetch(`http://127.0.0.1:${context.server.port}/api/session`, { method: 'POST' })
    expect(response.status).toBe(201)
    expect(typeof (await response.json()).token).toBe('string')
  })

  it('refuses unknown properties and bodies that are not an object with E_BAD_REQUEST, creating nobody', async () => {
    const before = await playerCount()
    const refused = [
      [{ x: 1 }, 'application/json', /must NOT have additional properties/],
      [{ clientSeed: 'abc' }, 'application/json', /must NOT have additional properties/],
      ['[1]', 'application/json', /must be object,null/],
      ['"guest"', 'application/json', /must be object,null/],
      ['42', 'application/json', /must be object,null/],
      ['hello', 'text/plain', /must be object,null/]
    ]
    for (const [payload, contentType, message] of refused) {
      const response = await post(payload, contentType)
      expect(response.status, JSON.stringify(payload)).toBe(400)
      expect(response.body).toEqual({ code: 'E_BAD_REQUEST', message: expect.stringMatching(message) })
    }
    expect(await playerCount()).toBe(before)
  })
})
