import { requirePlayer } from '../auth.js'
import { gameError } from '../errors.js'
import { dropList, dropRecord, errors } from './schemas.js'

/**
 * A player's own drops, newest first in the order they were played
 * (store/drop-pages.js; the server seed appears on a drop
 * only once it has been revealed). Another player's drop is read only
 * through its share link (routes/share.js), whose token needs its seed.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ store: import('../store/ledger-store.js').LedgerStore, authGuard: import('../limits/auth-guard.js').AuthGuard }} services
 */
export default async function dropRoutes (app, { store, authGuard }) {
  const asPlayer = requirePlayer(store, authGuard)

  app.get('/api/drops', {
    onRequest: asPlayer,
    schema: {
      summary: "The caller's drops, newest first (in the order they were played: seed by seed, nonce by nonce); page with ?before=<id of the previous page's last drop> (any other id: 404 E_NOT_FOUND)",
      querystring: {
        type: 'object',
        properties: {
          limit: { type: 'integer', minimum: 1, maximum: 500, default: 50 },
          before: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER }
        },
        additionalProperties: false
      },
      response: { 200: dropList, ...errors(400, 401, 404) }
    }
  }, async (request) => {
    const { limit, before } = request.query
    return { drops: await store.listDrops({ playerId: request.playerId, beforeId: before, limit }) }
  })

  app.get('/api/drops/:id', {
    onRequest: asPlayer,
    schema: {
      summary: 'One of the caller\'s drops',
      params: { type: 'object', properties: { id: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER } }, required: ['id'] },
      response: { 200: dropRecord, ...errors(400, 401, 404) }
    }
  }, async (request) => {
    const drop = await store.getDrop(request.params.id)
    // Someone else's drop reads as no drop: a 403 would tell a caller which ids exist.
    if (!drop || drop.playerId !== request.playerId) throw gameError('E_NOT_FOUND', `you have no drop ${request.params.id}`)
    return drop
  })
}
