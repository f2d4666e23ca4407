import { createHash, timingSafeEqual } from 'node:crypto'
import { gameError } from './errors.js'

/** Session tokens are 32 random bytes in hex; anything else is refused before a lookup. */
const TOKEN_PATTERN = /^[0-9a-f]{64}$/

/** The database keeps only this digest of a session token. @param {string} token */
export function hashToken (token) {
  return createHash('sha256').update(token).digest('hex')
}

/** @param {import('fastify').FastifyRequest} request @returns {string | null} */
export function bearerToken (request) {
  const header = request.headers.authorization
  if (typeof header !== 'string') return null
  const match = /^Bearer\s+(\S+)\s*$/i.exec(header)
  return match ? match[1] : null
}

/**
 * The player a session token belongs to, or null.
 * @param {{ findPlayerIdByTokenHash: (hash: string) => Promise<string | null> }} store
 * @param {unknown} token
 */
export async function playerIdForToken (store, token) {
  if (typeof token !== 'string' || !TOKEN_PATTERN.test(token)) return null
  return store.findPlayerIdByTokenHash(hashToken(token))
}

/**
 * The operator token check of a request, as a verdict rather than an
 * error: `{ valid: true }`, or `{ valid: false, code, message }` with the
 * code a refusing route answers (E_UNAUTHORIZED: no token; E_FORBIDDEN: a
 * wrong one, counted against the address; E_RATE_LIMITED, with
 * `retryAfter` in seconds: the address is blocked, and the token is then
 * not looked at, limits/auth-guard.js). The tokens are compared as
 * SHA-256 digests with timingSafeEqual: equal lengths whatever the input,
 * and no early exit that would leak how much of a guess was right.
 * @param {string} operatorToken @param {import('./limits/auth-guard.js').AuthGuard} guard
 * @returns {(request: import('fastify').FastifyRequest) => Promise<{ valid: boolean, code?: string, message?: string, retryAfter?: number }>}
 */
export function operatorTokenCheck (operatorToken, guard) {
  const expected = createHash('sha256').update(operatorToken).digest()
  return async function checkOperator (request) {
    const block = await guard.blocked('operator', request.ip)
    if (block) return { valid: false, code: 'E_RATE_LIMITED', ...block }
    const token = bearerToken(request)
    if (token === null) return { valid: false, code: 'E_UNAUTHORIZED', message: 'operator token required: Authorization: Bearer OPERATOR_TOKEN' }
    const given = createHash('sha256').update(token).digest()
    if (!timingSafeEqual(given, expected)) {
      await guard.failed('operator', request.ip)
      return { valid: false, code: 'E_FORBIDDEN', message: 'wrong operator token' }
    }
    return { valid: true }
  }
}

/**
 * onRequest hook for the operator API (before any schema check): the
 * check above, a refusal thrown as its error (401, 403, or 429 with
 * Retry-After).
 * @param {string} operatorToken @param {import('./limits/auth-guard.js').AuthGuard} guard
 */
export function requireOperator (operatorToken, guard) {
  const check = operatorTokenCheck(operatorToken, guard)
  return async function operatorOnly (request, reply) {
    const verdict = await check(request)
    if (verdict.valid) return
    if (verdict.retryAfter) reply.header('retry-after', String(verdict.retryAfter))
    throw gameError(verdict.code, verdict.message)
  }
}

/**
 * onRequest hook for player routes (before any schema check): sets request.playerId from the bearer token.
 * An unknown token counts against the address, as a wrong operator token does.
 * @param {{ findPlayerIdByTokenHash: (hash: string) => Promise<string | null> }} store
 * @param {import('./limits/auth-guard.js').AuthGuard} guard
 */
export function requirePlayer (store, guard) {
  return async function playerOnly (request, reply) {
    await guard.admit('player', request.ip, reply)
    const token = bearerToken(request)
    if (token === null) throw gameError('E_UNAUTHORIZED', 'session token required: Authorization: Bearer TOKEN (POST /api/session creates one)')
    const playerId = await playerIdForToken(store, token)
    if (!playerId) {
      await guard.failed('player', request.ip)
      throw gameError('E_UNAUTHORIZED', 'unknown session token')
    }
    request.playerId = playerId
  }
}
