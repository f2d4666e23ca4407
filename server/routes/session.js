import { createSession } from '../game/sessions.js'
import { requirePlayer } from '../auth.js'
import { toCredits } from '../game/money.js'
import { errors, noOptionsBody } from './schemas.js'

const sessionReply = {
  type: 'object',
  properties: {
    token: { type: 'string' },
    playerId: { type: 'string' },
    balance: { type: 'number', description: 'credits, up to three decimals' },
    serverSeedHash: { type: 'string' },
    clientSeed: { type: 'string' },
    nonce: { type: 'integer' }
  }
}

const { token, ...meProperties } = sessionReply.properties

/**
 * POST /api/session: a new guest player (play money) and its token.
 * GET /api/me: the caller's balance and fairness state.
 * @param {import('fastify').FastifyInstance} app
 * @param {object} services
 * @param {{ sessionRateLimit: number, startingBalance: number }} services.config
 * @param {import('../store/ledger-store.js').LedgerStore} services.store
 * @param {import('../game/accounts.js').AccountBook} services.accounts
 * @param {import('../limits/auth-guard.js').AuthGuard} services.authGuard
 */
export default async function sessionRoutes (app, { config, store, accounts, authGuard }) {
  app.post('/api/session', {
    config: { rateLimit: { max: config.sessionRateLimit, timeWindow: 60_000 } },
    schema: {
      summary: 'Create a guest session',
      body: noOptionsBody,
      response: { 201: sessionReply, ...errors(400, 429) }
    }
  }, async (request, reply) => {
    reply.code(201)
    return createSession(store, config)
  })

  app.get('/api/me', {
    onRequest: requirePlayer(store, authGuard),
    schema: {
      summary: "The caller's balance, active seed commitment, client seed and next nonce",
      response: {
        200: {
          type: 'object',
          properties: { ...meProperties, createdAt: { type: 'string' }, room: { type: ['string', 'null'] } }
        },
        ...errors(401)
      }
    }
  }, async (request) => accounts.withAccount(request.playerId, (account) => {
    const connection = [...account.connections].find((c) => c.room)
    return {
      playerId: account.playerId,
      balance: toCredits(account.balance),
      serverSeedHash: account.seed.hash,
      clientSeed: account.clientSeed,
      nonce: account.seed.nextNonce,
      createdAt: new Date(account.createdAt).toISOString(),
      room: connection?.room.id ?? null
    }
  }))
}
