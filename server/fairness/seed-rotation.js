import { newServerSeed } from './seeds.js'

/**
 * Seed changes go through the ledger queue, after every drop accepted
 * before them, and the in-memory account switches only once the change is
 * committed. Drops accepted while a rotation is being written still use the
 * old seed: their drop seeds were fixed before the reveal went out, and the
 * reply reports how many nonces the old seed served in all.
 */

/**
 * Reveals the active server seed and commits a new one.
 * @param {import('../arena.js').Arena} arena
 * @param {import('../ledger/accounts.js').Account} account
 */
export async function rotateServerSeed (arena, account) {
  return arena.ledger.run(async () => {
    const old = account.seed
    const fresh = newServerSeed()
    await arena.store.rotateSeed({ playerId: account.playerId, oldSeedId: old.id, newSeed: fresh, at: Date.now() })
    account.seed = { ...fresh, nextNonce: 0 }
    return {
      previousServerSeed: old.seed,
      previousServerSeedHash: old.hash,
      previousNonce: old.nextNonce,
      serverSeedHash: fresh.hash,
      clientSeed: account.clientSeed,
      nonce: 0
    }
  })
}

/**
 * @param {import('../arena.js').Arena} arena
 * @param {import('../ledger/accounts.js').Account} account
 * @param {string} clientSeed already validated
 */
export async function setClientSeed (arena, account, clientSeed) {
  return arena.ledger.run(async () => {
    await arena.store.commitBatch({ drops: [], settlements: [], balances: [], nonces: [], clientSeeds: [{ playerId: account.playerId, clientSeed }] })
    account.clientSeed = clientSeed
    return { clientSeed, serverSeedHash: account.seed.hash, nonce: account.seed.nextNonce }
  })
}
