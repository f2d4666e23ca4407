import { requirePlayer } from '../auth.js'
import { rotateServerSeed, setClientSeed } from '../fairness/seed-rotation.js'
import { clientSeed, errors } from './schemas.js'
import { gameError } from '../errors.js'

const seedState = {
  type: 'object',
  properties: { clientSeed: { type: 'string' }, serverSeedHash: { type: 'string' }, nonce: { type: 'integer' } }
}

/**
 * The player's fairness seeds: list (the active one by hash only), rotate
 * (reveal the active seed, commit a new one) and set the client seed.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ arena: import('../arena.js').Arena, authGuard: import('../limits/auth-guard.js').AuthGuard }} options
 */
export default async function seedRoutes (app, { arena, authGuard }) {
  const { store } = arena
  const asPlayer = requirePlayer(store, authGuard)

  /** Holds the caller's account for the duration of `work`. */
  async function withAccount (request, work) {
    const account = await arena.accounts.acquire(request.playerId)
    if (!account) throw gameError('E_UNAUTHORIZED', 'unknown player')
    try {
      return await work(account)
    } finally {
      arena.accounts.release(account)
    }
  }

  app.get('/api/seeds', {
    onRequest: asPlayer,
    schema: {
      summary: "The caller's server seeds: the active one by its hash only, revealed ones in full",
      response: {
        200: {
          type: 'object',
          properties: {
            active: {
              type: 'object',
              properties: { serverSeedHash: { type: 'string' }, clientSeed: { type: 'string' }, nonce: { type: 'integer' }, createdAt: { type: 'string' } }
            },
            revealed: {
              type: 'array',
              items: {
                type: 'object',
                properties: { serverSeed: { type: 'string' }, serverSeedHash: { type: 'string' }, nonces: { type: 'integer' }, createdAt: { type: 'string' }, revealedAt: { type: 'string' } }
              }
            }
          }
        },
        ...errors(401)
      }
    }
  }, async (request) => withAccount(request, async (account) => {
    const seeds = await store.listSeeds(account.playerId)
    const active = seeds.find((seed) => seed.active)
    return {
      active: { serverSeedHash: account.seed.hash, clientSeed: account.clientSeed, nonce: account.seed.nextNonce, createdAt: active?.createdAt },
      revealed: seeds.filter((seed) => !seed.active && seed.serverSeed !== null).map((seed) => ({
        serverSeed: seed.serverSeed,
        serverSeedHash: seed.serverSeedHash,
        nonces: seed.nonce,
        createdAt: seed.createdAt,
        revealedAt: seed.revealedAt
      }))
    }
  }))

  app.post('/api/seeds/rotate', {
    onRequest: asPlayer,
    schema: {
      summary: 'Reveal the active server seed and commit a new one',
      response: {
        200: {
          type: 'object',
          properties: {
            previousServerSeed: { type: 'string' },
            previousServerSeedHash: { type: 'string' },
            previousNonce: { type: 'integer' },
            ...seedState.properties
          }
        },
        ...errors(401)
      }
    }
  }, async (request) => withAccount(request, (account) => rotateServerSeed(arena, account)))

  app.put('/api/seeds/client', {
    onRequest: asPlayer,
    schema: {
      summary: 'Set the client seed used by the next drops',
      body: { type: 'object', properties: { clientSeed }, required: ['clientSeed'], additionalProperties: false },
      response: { 200: seedState, ...errors(400, 401) }
    }
  }, async (request) => withAccount(request, (account) => setClientSeed(arena, account, request.body.clientSeed)))
}
