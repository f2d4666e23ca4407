import { operatorTokenCheck } from '../auth.js'
import { noOptionsBody } from './schemas.js'

/** The refusals the check reports (in its 200 body), each as the operator routes would answer it. */
const REFUSALS = ['E_UNAUTHORIZED', 'E_FORBIDDEN', 'E_RATE_LIMITED']

const verdict = {
  type: 'object',
  properties: {
    valid: { type: 'boolean', description: 'true: the operator routes take this token' },
    code: { type: 'string', enum: REFUSALS, description: 'why not: E_UNAUTHORIZED no token, E_FORBIDDEN a wrong one, E_RATE_LIMITED this address is blocked (the token was not looked at)' },
    message: { type: 'string' },
    retryAfter: { type: 'integer', minimum: 1, description: 'E_RATE_LIMITED: seconds left of the block' }
  },
  required: ['valid']
}

/**
 * POST /api/audit/token-check: whether the bearer token is the operator
 * token, always answered 200 so that the operator page can sign in without
 * a refused request in the browser's console (Chromium logs every 4xx a
 * page's fetch gets). It is the operator routes' own check
 * (auth.js, operatorTokenCheck): a wrong token counts against the address
 * as a 403 there does, and a blocked address is told so (with the seconds
 * left) whatever token it sends; the operator routes keep answering
 * 401/403/429. Registered beside the audit routes, not among them: their
 * plugin refuses any request without the right token.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ operatorToken: string, authGuard: import('../limits/auth-guard.js').AuthGuard }} services
 */
export default async function auditTokenCheckRoute (app, { operatorToken, authGuard }) {
  const check = operatorTokenCheck(operatorToken, authGuard)
  app.post('/api/audit/token-check', {
    // api-docs.js: the token is checked here, not required.
    config: { tokenCheck: true },
    schema: {
      summary: 'Whether a token is the operator token (a 200 either way; a wrong one counts against the address)',
      description: 'Send the token to check as `Authorization: Bearer …`, no body. The answer is `{ valid: true }`, or `{ valid: false, code, message }` with the code the operator routes would refuse it with; while the address is blocked for wrong tokens, `E_RATE_LIMITED` with `retryAfter` (seconds), whatever the token.',
      body: noOptionsBody,
      response: { 200: verdict }
    }
  }, async (request) => check(request))
}
