import { ENGINE_VERSION, ENGINE_VERSIONS } from '../../engine/index.js'
import { errorReply } from './schemas.js'

/**
 * GET /api/health: liveness for load balancers and the client's about box.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ health: () => import('../arena.js').ArenaHealth, rateLimit: number }} services
 *   health: the game's state now; rateLimit: MONITORING_RATE_LIMIT
 */
export default async function healthRoutes (app, { health, rateLimit }) {
  app.get('/api/health', {
    // A budget of its own (MONITORING_RATE_LIMIT), apart from HTTP_RATE_LIMIT: probes
    // never compete with the API, and one client cannot make the server answer thousands a second.
    config: { rateLimit: { max: rateLimit, timeWindow: 60_000 } },
    schema: {
      summary: 'Liveness',
      response: {
        429: errorReply,
        200: {
          type: 'object',
          properties: { status: { type: 'string' }, engineVersion: { type: 'string' }, engineVersions: { type: 'array', items: { type: 'string' } }, store: { type: 'string' }, settlementsWaiting: { type: 'integer' }, tick: { type: 'integer' }, rooms: { type: 'integer' } }
        }
      }
    }
  }, async () => {
    const { accepting, settlementsWaiting, store, tick, rooms } = health()
    return {
      // degraded: payouts the ledger refused are waiting for their retry (a full disk, a lost database)
      status: !accepting ? 'closing' : settlementsWaiting > 0 ? 'degraded' : 'ok',
      engineVersion: ENGINE_VERSION,
      engineVersions: ENGINE_VERSIONS,
      store,
      settlementsWaiting,
      tick,
      rooms
    }
  })
}
