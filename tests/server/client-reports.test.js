/**
 * POST /api/client-errors: a page's report (E_DESYNC from a seeds-mode
 * page) is accepted, a malformed one is refused with a code, and a flood
 * of reports logs at most the budget's lines a minute.
 */
import { describe, it, expect } from 'vitest'
import { useServerOn } from './helpers/server.js'
import { logBudget } from '../../server/routes/client-reports.js'

const desync = { code: 'E_DESYNC', message: 'hash differs', page: 'player', room: '16-medium', tick: 1234, serverHash: '0123456789abcdef', localHash: 'fedcba9876543210', ballsInFlight: 3, engineVersion: '2.0.0' }

describe('POST /api/client-errors', () => {
  const context = useServerOn('sqlite')
  const post = (body) => context.server.app.inject({ method: 'POST', url: '/api/client-errors', payload: body })

  it('accepts a report and refuses malformed ones with a code', async () => {
    const accepted = await post(desync)
    expect(accepted.statusCode).toBe(202)
    expect(accepted.json()).toEqual({ received: true })
    expect((await post({ code: 'E_DESYNC', message: 'm', page: 'player' })).statusCode).toBe(202)
    for (const bad of [{ ...desync, code: 'desync' }, { ...desync, extra: 1 }, { ...desync, serverHash: 'x'.repeat(16) }, { code: 'E_DESYNC', page: 'player' }, { ...desync, message: 'm'.repeat(501) }, { ...desync, tick: -1 }]) {
      const refused = await post(bad)
      expect(refused.statusCode, JSON.stringify(bad)).toBe(400)
      expect(refused.json().code).toBe('E_BAD_REQUEST')
    }
  })

  it('logs at most the budget a window, and says how many went unlogged', () => {
    const budget = logBudget(3, 60_000)
    const at = [0, 1, 2, 3, 4, 59_999, 60_000, 60_001].map((now) => budget(now))
    expect(at).toEqual([0, 0, 0, null, null, null, 3, 0])
  })
})
