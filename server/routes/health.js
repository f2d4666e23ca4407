import { ENGINE_VERSION, ENGINE_VERSIONS } from '../../engine/index.js'
import { errorReply } from './schemas.js'

/**
 * GET /api/health: liveness for load balancers and the client's about box.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ arena: import('../arena.js').Arena }} options
 */
export default async function healthRoutes (app, { arena }) {
  app.get('/api/health', {
    // A budget of its own (MONITORING_RATE_LIMIT), apart from HTTP_RATE_LIMIT: probes
    // never compete with the API, and one client cannot make the server answer thousands a second.
    config: { rateLimit: { max: arena.config.monitoringRateLimit, timeWindow: 60_000 } },
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
  }, async () => ({
    // degraded: payouts the ledger refused are waiting for their retry (a full disk, a lost database)
    status: !arena.accepting ? 'closing' : arena.drops.settlementsWaiting > 0 ? 'degraded' : 'ok',
    engineVersion: ENGINE_VERSION,
    engineVersions: ENGINE_VERSIONS,
    store: arena.store.kind,
    settlementsWaiting: arena.drops.settlementsWaiting,
    tick: arena.scheduler.ticks,
    rooms: arena.rooms.size
  }))
}
