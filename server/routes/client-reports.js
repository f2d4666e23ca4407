import { errors } from './schemas.js'

/** Reports one address may send a minute: enough for any real page, too few to fill the logs. */
const REPORTS_PER_MINUTE = 30

/**
 * POST /api/client-errors: a page tells the server something went wrong
 * on its side that the server would not see otherwise — a seeds-mode page
 * whose simulation disagrees with the room's flight hash (E_DESYNC) and
 * has switched that room to snapshots. The report is validated, logged at
 * warn level with the sender's address, and answered 202; it changes
 * nothing in the game. Anyone may send one (a page reports even when its
 * session is gone), so it is rate limited per address and every field is
 * bounded.
 * @param {import('fastify').FastifyInstance} app
 */
export default async function clientReportRoutes (app) {
  app.post('/api/client-errors', {
    config: { rateLimit: { max: REPORTS_PER_MINUTE, timeWindow: '1 minute' } },
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
    request.log.warn({ report: request.body, remoteAddress: request.ip }, `client error report: ${request.body.code}`)
    reply.code(202)
    return { received: true }
  })
}
