import { BalanceSync } from './balance-sync.js'
import { SeedSync } from './seed-sync.js'

/**
 * The account feed of a process in a cluster (../coordination/account-feed.js):
 * committed balances are announced and other processes' re-read
 * (balance-sync.js); seed rotations are announced and answered once the
 * other processes have switched (seed-sync.js).
 * @implements {import('../coordination/account-feed.js').AccountFeed}
 */
export class ClusterAccountFeed {
  /**
   * @param {object} options
   * @param {import('./cluster-presence.js').ClusterPresence} options.presence
   * @param {import('./shared-ledger.js').SharedLedgerStore} options.store
   * @param {import('pino').Logger} options.log
   */
  constructor ({ presence, store, log }) {
    this.presence = presence
    this.store = store
    this.log = log
    /** Other processes' balance changes reach the accounts held here. */
    this.balances = null
    /** Other processes' seed rotations reach the accounts held here. */
    this.seeds = null
  }

  /** @param {import('../coordination/account-feed.js').FeedServices} services */
  async start ({ accounts, onBalanceChanged }) {
    const { redis, nodeId } = this.presence
    await this.presence.connect()
    this.balances = new BalanceSync({ redis, nodeId, accounts, onBalanceChanged, store: this.store, log: this.log })
    this.seeds = new SeedSync({ redis, nodeId, accounts, store: this.store, log: this.log })
    await this.balances.start()
    await this.seeds.start()
  }

  /** @param {Iterable<string>} playerIds */
  balancesCommitted (playerIds) { this.balances.committed(playerIds) }

  /** @param {import('../game/accounts.js').Account} account */
  seedRotated (account) { return this.seeds.rotated(account.playerId, account.seed.id) }

  /** @param {import('../game/accounts.js').Account} account */
  seedOutdated (account) { return this.seeds.refresh(account) }

  async close () {
    await this.balances?.close()
    await this.seeds?.close()
  }
}
