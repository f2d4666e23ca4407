import { requirePlayer } from '../auth.js'
import { clientSeed, errors } from './schemas.js'

const seedState = {
  type: 'object',
  properties: { clientSeed: { type: 'string' }, serverSeedHash: { type: 'string' }, nonce: { type: 'integer' } }
}

const rotationReply = {
  type: 'object',
  properties: { previousServerSeed: { type: 'string' }, previousServerSeedHash: { type: 'string' }, previousNonce: { type: 'integer' }, ...seedState.properties }
}

/** GET /api/seeds's reply: the active seed by its hash, the revealed ones in full. */
function seedList (account, seeds) {
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
}

/**
 * The player's fairness seeds: list (the active one by hash only), rotate
 * (reveal the active seed, commit a new one) and set the client seed.
 * @param {import('fastify').FastifyInstance} app
 * @param {object} services
 * @param {import('../store/ledger-store.js').LedgerStore} services.store
 * @param {import('../game/accounts.js').AccountBook} services.accounts
 * @param {import('../game/seed-changes.js').SeedChanges} services.seedChanges
 * @param {import('../limits/auth-guard.js').AuthGuard} services.authGuard
 */
export default async function seedRoutes (app, { store, accounts, seedChanges, authGuard }) {
  const asPlayer = requirePlayer(store, authGuard)

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
  }, async (request) => accounts.withAccount(request.playerId, async (account) => seedList(account, await store.listSeeds(account.playerId))))

  app.post('/api/seeds/rotate', {
    onRequest: asPlayer,
    schema: {
      summary: 'Reveal the active server seed and commit a new one',
      response: { 200: rotationReply, ...errors(401) }
    }
  }, async (request) => accounts.withAccount(request.playerId, (account) => seedChanges.rotateServerSeed(account)))

  app.put('/api/seeds/client', {
    onRequest: asPlayer,
    schema: {
      summary: 'Set the client seed used by the next drops',
      body: { type: 'object', properties: { clientSeed }, required: ['clientSeed'], additionalProperties: false },
      response: { 200: seedState, ...errors(400, 401) }
    }
  }, async (request) => accounts.withAccount(request.playerId, (account) => seedChanges.setClientSeed(account, request.body.clientSeed)))
}
