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
 * onRequest hook for the operator API (before any schema check). The tokens are compared as SHA-256
 * digests with timingSafeEqual: equal lengths whatever the input, and no
 * early exit that would leak how much of a guess was right.
 * Missing token → 401 E_UNAUTHORIZED; wrong token → 403 E_FORBIDDEN, counted
 * against the address, which past its budget gets 429 E_RATE_LIMITED for
 * a while, whatever token it sends (limits/auth-guard.js).
 * @param {string} operatorToken @param {import('./limits/auth-guard.js').AuthGuard} guard
 */
export function requireOperator (operatorToken, guard) {
  const expected = createHash('sha256').update(operatorToken).digest()
  return async function operatorOnly (request, reply) {
    await guard.admit('operator', request.ip, reply)
    const token = bearerToken(request)
    if (token === null) throw gameError('E_UNAUTHORIZED', 'operator token required: Authorization: Bearer OPERATOR_TOKEN')
    const given = createHash('sha256').update(token).digest()
    if (!timingSafeEqual(given, expected)) {
      await guard.failed('operator', request.ip)
      throw gameError('E_FORBIDDEN', 'wrong operator token')
    }
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
