import { clientSeedBatch } from './drop.js'
import { newServerSeed } from '../fairness/seeds.js'

/**
 * Seed changes go through the ledger queue, after every drop accepted
 * before them and before every drop accepted after them.
 * - A rotation stops the player's drops from the moment it is asked for
 *   until it is answered (E_SEED_ROTATING, nothing debited): the drops
 *   accepted before it are written before it, none is taken on the old seed
 *   after, so no drop is ever recorded on a seed after its `revealed_at`
 *   (stamped once those drops are written). It switches the in-memory
 *   account once committed, tells the other processes (a cluster's workers
 *   switch before it answers), and the reply reports how many nonces the old
 *   seed served in all.
 * - A client seed takes effect when the server receives it, exactly as a
 *   `drop { clientSeed }` does: memory now, the ledger in the same order
 *   (the queue), so whichever of the two paths came last holds in both.
 */

/**
 * A player's seed changes, given only what they touch: the ledger queue,
 * the store and the account feed (which tells the other processes).
 */
export class SeedChanges {
  /**
   * @param {object} services
   * @param {{ run: <T>(work: () => Promise<T>) => Promise<T> }} services.ledger the group commit's queue (drop.js)
   * @param {import('../store/ledger-store.js').LedgerStore} services.store
   * @param {import('../coordination/account-feed.js').AccountFeed} services.feed
   */
  constructor ({ ledger, store, feed }) {
    this.ledger = ledger
    this.store = store
    this.feed = feed
  }

  /**
   * Reveals the active server seed and commits a new one.
   * @param {import('./accounts.js').Account} account
   */
  async rotateServerSeed (account) {
    account.seedRotations++
    try {
      const reply = await this.ledger.run(async () => {
        const old = account.seed
        const fresh = newServerSeed()
        // Every drop on `old` is written by now (the queue), each stamped before this.
        await this.store.rotateSeed({ playerId: account.playerId, oldSeedId: old.id, newSeed: fresh, at: Date.now() })
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
      // Before the answer (and outside the ledger queue): the next drop on any process uses the new seed.
      await this.feed.seedRotated(account)
      return reply
    } catch (error) {
      // Rotated by another process first (clustered): this one held an old seed.
      if (error?.code === 'E_SEED_ROTATED') await this.feed.seedOutdated(account)
      throw error
    } finally {
      account.seedRotations--
    }
  }

  /**
   * @param {import('./accounts.js').Account} account
   * @param {string} clientSeed already validated
   */
  async setClientSeed (account, clientSeed) {
    const previous = account.clientSeed
    account.clientSeed = clientSeed
    try {
      await this.ledger.run(() => this.store.commitBatch(clientSeedBatch(account.playerId, clientSeed)))
    } catch (error) {
      // Not written: back to what the ledger has, unless a later change replaced it meanwhile.
      if (account.clientSeed === clientSeed) account.clientSeed = previous
      throw error
    }
    return { clientSeed, serverSeedHash: account.seed.hash, nonce: account.seed.nextNonce }
  }
}
