import { errors } from './schemas.js'

/** Reports logged a minute, over all senders: a flood of reports cannot fill the logs. */
const LOGGED_PER_MINUTE = 30

/**
 * POST /api/client-errors: a page tells the server something went wrong
 * on its side that the server would not see otherwise — a seeds-mode page
 * whose simulation disagrees with the room's flight hash (E_DESYNC) and
 * has switched that room to snapshots. The report is validated, logged at
 * warn level with the sender's address, and answered 202; it changes
 * nothing in the game. Anyone may send one (a page reports even when its
 * session is gone): every field is bounded, the route is under the HTTP
 * rate limit per address like every other, and at most LOGGED_PER_MINUTE
 * reports a minute are logged (the rest are counted in the next logged one).
 * @param {import('fastify').FastifyInstance} app
 */
export default async function clientReportRoutes (app) {
  const budget = logBudget(LOGGED_PER_MINUTE, 60_000)
  app.post('/api/client-errors', {
    schema: {
      summary: "A page's report of an error only it can see (E_DESYNC: its simulation of a room disagreed with the server's flight hash)",
      body: {
        type: 'object',
        additionalProperties: false,
        required: ['code', 'message', 'page'],
        properties: {
          code: { type: 'string', pattern: '^E_[A-Z_]{1,40}$' },
          message: { type: 'string', maxLength: 500 },
          page: { type: 'string', enum: ['player', 'audit'] },
          room: { type: 'string', maxLength: 32 },
          tick: { type: 'integer', minimum: 0, maximum: 0xffffffff },
          serverHash: { type: 'string', pattern: '^[0-9a-f]{16}$' },
          localHash: { type: 'string', pattern: '^[0-9a-f]{16}$' },
          ballsInFlight: { type: 'integer', minimum: 0, maximum: 100000 },
          engineVersion: { type: 'string', maxLength: 16 }
        }
      },
      response: { 202: { type: 'object', properties: { received: { type: 'boolean' } } }, ...errors(400) }
    }
  }, async (request, reply) => {
    const unlogged = budget(Date.now())
    if (unlogged !== null) request.log.warn({ report: request.body, remoteAddress: request.ip, unlogged }, `client error report: ${request.body.code}`)
    reply.code(202)
    return { received: true }
  })
}

/**
 * At most `limit` log lines per `windowMs`: the returned function says, for
 * a report at `now`, null (do not log it) or how many went unlogged since
 * the last one that was.
 * @param {number} limit @param {number} windowMs
 */
export function logBudget (limit, windowMs) {
  let windowStart = -Infinity
  let logged = 0
  let unlogged = 0
  return (now) => {
    if (now - windowStart >= windowMs) {
      windowStart = now
      logged = 0
    }
    if (logged >= limit) {
      unlogged++
      return null
    }
    logged++
    const skipped = unlogged
    unlogged = 0
    return skipped
  }
}
