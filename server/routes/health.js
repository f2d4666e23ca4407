import { ENGINE_VERSION, ENGINE_VERSIONS } from '../../engine/index.js'

/**
 * GET /api/health: liveness for load balancers and the client's about box.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ arena: import('../arena.js').Arena }} options
 */
export default async function healthRoutes (app, { arena }) {
  app.get('/api/health', {
    config: { rateLimit: false },
    schema: {
      summary: 'Liveness',
      response: {
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
