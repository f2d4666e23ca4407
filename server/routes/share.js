import { createHash, timingSafeEqual } from 'node:crypto'
import { SHARE_TOKEN_LENGTH, shareTokenMessage, shareTokenOf } from '../../protocol/share-token.js'
import { gameError } from '../errors.js'
import { errors } from './schemas.js'

/**
 * A drop's share token (protocol/share-token.js: the first
 * SHARE_TOKEN_LENGTH hex characters of sha256("share:" + its drop seed)),
 * with node:crypto. Only who was told a drop's seed can make it: its player
 * (GET /api/drops) and the players of its room (the seed is announced
 * there, and the player page checks other players' drops through this
 * route); nobody can walk the ids to read other players' drops.
 * @param {string} dropSeed
 */
export function shareToken (dropSeed) {
  return shareTokenOf(createHash('sha256').update(shareTokenMessage(dropSeed), 'utf8').digest('hex'))
}

/** How a shared drop names its player: the first six characters of the id, never the whole id. @param {string} playerId */
export function playerTag (playerId) {
  return playerId.length > 8 ? `${playerId.slice(0, 6)}…` : playerId
}

const sharedDrop = {
  type: 'object',
  properties: {
    id: { type: 'integer' },
    player: { type: 'string', description: 'the player by tag only (the first characters of the id)' },
    room: { type: 'string' },
    rows: { type: 'integer' },
    risk: { type: 'string' },
    engineVersion: { type: 'string' },
    bet: { type: 'integer' },
    bucket: { type: ['integer', 'null'] },
    multiplier: { type: ['number', 'null'] },
    payout: { type: ['number', 'null'] },
    ticks: { type: ['integer', 'null'] },
    stateHash: { type: ['string', 'null'] },
    status: { type: 'string', enum: ['in_flight', 'settled'] },
    createdAt: { type: 'string' },
    settledAt: { type: ['string', 'null'] },
    serverSeedHash: { type: 'string', description: 'the commitment shown before the drop' },
    clientSeed: { type: 'string' },
    nonce: { type: 'integer' },
    dropSeed: { type: 'string' },
    serverSeed: { type: ['string', 'null'], description: 'null until the player rotates that seed (reveals it)' },
    verifiable: { type: 'boolean', description: 'the server seed is revealed: the whole chain can be checked' }
  }
}

/**
 * Share links: GET /api/share/:id/:token, one drop as anyone may see it,
 * with no token of a session: the player by tag only, the seeds, and the
 * server seed once revealed (never before). A wrong token is a 404 like
 * an unknown id. The page /share/:id/:token (client/share.html) replays
 * and verifies it in the viewer's browser; the player page verifies
 * another player's drop in its room feed with it (client/public-drop-check.js).
 * @param {import('fastify').FastifyInstance} app
 * @param {{ store: import('../store/ledger-store.js').LedgerStore }} services
 */
export default async function shareRoutes (app, { store }) {

  app.get('/api/share/:id/:token', {
    schema: {
      summary: 'A shared drop, for anyone with its link: the player by tag, its seeds, the server seed once revealed',
      params: {
        type: 'object',
        properties: {
          id: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER },
          token: { type: 'string', pattern: `^[0-9a-f]{${SHARE_TOKEN_LENGTH}}$` }
        },
        required: ['id', 'token']
      },
      response: { 200: sharedDrop, ...errors(400, 404) }
    }
  }, async (request) => {
    const { id, token } = request.params
    const drop = await store.getDrop(id)
    if (!drop || !timingSafeEqual(Buffer.from(shareToken(drop.dropSeed)), Buffer.from(token))) {
      throw gameError('E_NOT_FOUND', `no shared drop ${id} with this link`)
    }
    return {
      ...drop,
      player: playerTag(drop.playerId),
      serverSeed: drop.serverSeed ?? null,
      verifiable: Boolean(drop.serverSeed)
    }
  })
}
