/**
 * Every error the server reports, by name, in one place (after fastify's
 * lib/errors.js). HTTP replies carry `{ code, message }` with `status`;
 * WebSocket replies carry `{ type: "error", code, message, ref? }` and the
 * connection stays open unless the code's `close` says otherwise.
 */
export const ERROR_CODES = Object.freeze({
  E_BAD_MESSAGE: { status: 400, message: 'message is not valid JSON or does not match its schema' },
  E_UNKNOWN_TYPE: { status: 400, message: 'unknown message type' },
  E_BAD_REQUEST: { status: 400, message: 'request does not match its schema' },
  E_HEADERS_TOO_LARGE: { status: 431, message: 'request headers are too large' },
  E_TIMEOUT: { status: 408, message: 'the request did not arrive whole in time' },
  E_PAYLOAD_TOO_LARGE: { status: 413, message: 'request body is larger than 16 KiB' },
  E_UNSUPPORTED_MEDIA_TYPE: { status: 415, message: 'request body must be application/json' },
  E_BAD_BET: { status: 400, message: 'bet must be an integer within the table limits' },
  E_BAD_SEED: { status: 400, message: 'client seed must be 1 to 64 printable ASCII characters' },
  E_INSUFFICIENT_FUNDS: { status: 400, message: 'balance is lower than the bet' },
  E_UNKNOWN_ENGINE_VERSION: { status: 400, message: 'no such engine version on this server' },
  E_BAD_DELIVERY: { status: 400, message: 'join.delivery must be "seeds" or "snapshots" (the default)' },
  E_NOT_IN_ROOM: { status: 400, message: 'join a room first' },
  E_UNKNOWN_ROOM: { status: 404, message: 'no such room; room ids are ROWS-RISK or ROWS-RISK.N with rows 8..16, risk low, medium or high and N 2..8' },
  E_ROOM_FULL: { status: 409, message: 'too many balls in flight in this room; try again shortly' },
  E_SEED_ROTATING: { status: 409, message: 'your server seed is being rotated; drop again once the rotation is answered' },
  E_RATE_LIMITED: { status: 429, message: 'too many requests; slow down' },
  E_UNAUTHORIZED: { status: 401, message: 'missing or invalid token', close: 4401 },
  E_FORBIDDEN: { status: 403, message: 'not allowed' },
  E_NOT_FOUND: { status: 404, message: 'not found' },
  E_METHOD_NOT_ALLOWED: { status: 405, message: 'this path does not have this method; the Allow header lists the ones it has' },
  E_SLOW_CONSUMER: { status: 503, message: 'client is not reading fast enough', close: 1013 },
  E_TOO_MANY_CONNECTIONS: { status: 429, message: 'too many WebSocket connections from this address or to this server; close one or try again later', close: 4429 },
  E_UNAVAILABLE: { status: 503, message: 'server is shutting down' },
  E_INTERNAL: { status: 500, message: 'internal error' },
  // Clustering (server/cluster/): the reply to `join` carries `room`, and `owner` (a URL) or `retryAfterMs`.
  E_WRONG_NODE: { status: 421, message: 'this room runs on another server process; reconnect to `owner` (its /ws) and join again' },
  E_ROOM_MOVING: { status: 503, message: 'the process that ran this room stopped answering; retry after `retryAfterMs`' },
  E_SEED_ROTATED: { status: 409, message: 'the server seed was rotated by another connection; drop again to use the new one' }
})

/** A named, expected failure: its code decides the HTTP status and the protocol reply. */
export class GameError extends Error {
  /**
   * @param {keyof typeof ERROR_CODES} code
   * @param {string} [message] more specific than the default
   * @param {{ ref?: any, cause?: unknown }} [extra]
   */
  constructor (code, message, extra = {}) {
    const known = ERROR_CODES[code]
    if (!known) throw new TypeError(`unknown error code ${code}`)
    super(message ?? known.message, extra.cause === undefined ? undefined : { cause: extra.cause })
    this.name = 'GameError'
    this.code = code
    this.statusCode = known.status
    if (extra.ref !== undefined) this.ref = extra.ref
  }
}

/** @param {keyof typeof ERROR_CODES} code @param {string} [message] @param {object} [extra] */
export function gameError (code, message, extra) {
  return new GameError(code, message, extra)
}
