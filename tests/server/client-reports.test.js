/**
 * POST /api/client-errors: a page's report (E_DESYNC from a seeds-mode
 * page) is accepted and logged, a malformed one is refused with a code,
 * and one address cannot send more than the route's limit a minute.
 */
import { describe, it, expect } from 'vitest'
import { useServerOn } from './helpers/server.js'

const desync = { code: 'E_DESYNC', message: 'hash differs', page: 'player', room: '16-medium', tick: 1234, serverHash: '0123456789abcdef', localHash: 'fedcba9876543210', ballsInFlight: 3, engineVersion: '2.0.0' }

describe('POST /api/client-errors', () => {
  const context = useServerOn('sqlite')
  const post = (body) => context.server.app.inject({ method: 'POST', url: '/api/client-errors', payload: body })

  it('accepts a report, refuses malformed ones with a code, and limits how many one address sends', async () => {
    const accepted = await post(desync)
    expect(accepted.statusCode).toBe(202)
    expect(accepted.json()).toEqual({ received: true })
    for (const bad of [{ ...desync, code: 'desync' }, { ...desync, extra: 1 }, { ...desync, serverHash: 'x'.repeat(16) }, { code: 'E_DESYNC', page: 'player' }, { ...desync, message: 'm'.repeat(501) }]) {
      const refused = await post(bad)
      expect(refused.statusCode, JSON.stringify(bad)).toBe(400)
      expect(refused.json().code).toBe('E_BAD_REQUEST')
    }
    let limited = null
    for (let i = 0; i < 40 && limited === null; i++) {
      const response = await post(desync)
      if (response.statusCode === 429) limited = response
    }
    expect(limited?.json().code).toBe('E_RATE_LIMITED')
  })
})
