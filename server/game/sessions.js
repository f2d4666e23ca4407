import { randomBytes } from 'node:crypto'
import { hashToken } from '../auth.js'
import { newClientSeed, newServerSeed } from '../fairness/seeds.js'
import { toMilli } from './money.js'

/**
 * Creates a guest player with the starting play-money balance, a committed
 * server seed and a random client seed. The token is returned once and
 * only its SHA-256 is stored.
 * @param {any} store
 * @param {{ startingBalance: number }} config startingBalance in credits
 */
export async function createSession (store, { startingBalance }) {
  const token = randomBytes(32).toString('hex')
  const playerId = randomBytes(8).toString('hex')
  const seed = newServerSeed()
  const clientSeed = newClientSeed()
  await store.createPlayer({ id: playerId, tokenHash: hashToken(token), balance: toMilli(startingBalance), clientSeed, createdAt: Date.now(), seed })
  return { token, playerId, balance: startingBalance, serverSeedHash: seed.hash, clientSeed, nonce: 0 }
}
