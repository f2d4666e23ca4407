import { subscribeToNotices, closeNotices } from './notice-channel.js'

/** Redis channel on which processes announce the players whose balance they just committed. */
export const BALANCE_CHANNEL = 'plinko:balances'

/**
 * Keeps the balances this process holds in memory current when another
 * process changes them (one player connected to two processes). After each
 * committed batch a process publishes the ids of the players it changed;
 * the others re-read those players' committed balance from PostgreSQL —
 * only for accounts they hold — and report the new balance
 * (`onBalanceChanged`: the arena applies it and tells the player's
 * connections). A re-read is dropped if one of this process's own
 * batches for that player committed meanwhile (that balance is newer).
 * Balances are never decided here: PostgreSQL's conditional debits do that.
 */
export class BalanceSync {
  /**
   * @param {object} options
   * @param {import('ioredis').Redis} options.redis the process's connection (publishing); a duplicate subscribes
   * @param {string} options.nodeId
   * @param {{ held: (playerId: string) => import('../game/accounts.js').Account | undefined }} options.accounts the account book
   * @param {(account: import('../game/accounts.js').Account, balance: number) => void} options.onBalanceChanged
   *   another process committed this balance (milli-credits) for an account held here
   * @param {{ readBalance: (playerId: string) => Promise<number | null> }} options.store
   * @param {import('pino').Logger} options.log
   */
  constructor ({ redis, nodeId, accounts, onBalanceChanged, store, log }) {
    this.redis = redis
    this.nodeId = nodeId
    this.accounts = accounts
    this.onBalanceChanged = onBalanceChanged
    this.store = store
    this.log = log
    this.subscriber = null
    /** players being re-read → whether another notice came meanwhile */
    this._refreshing = new Map()
    this.stats = { received: 0, refreshed: 0 }
  }

  async start () {
    this.subscriber = await subscribeToNotices({
      redis: this.redis,
      channels: [BALANCE_CHANNEL],
      what: 'balance notices',
      log: this.log,
      onNotice: (channel, notice) => this._received(notice)
    })
  }

  /** After a committed batch: tell the other processes whose balances changed. @param {Iterable<string>} playerIds */
  committed (playerIds) {
    const players = [...playerIds]
    if (players.length === 0) return
    this.redis.publish(BALANCE_CHANNEL, JSON.stringify({ node: this.nodeId, players }))
      .catch((error) => this.log.warn({ err: error }, 'could not publish balance changes'))
  }

  /** @param {Record<string, any>} notice */
  _received (notice) {
    if (notice.node === this.nodeId || !Array.isArray(notice.players)) return
    this.stats.received++
    for (const playerId of notice.players) {
      const account = typeof playerId === 'string' ? this.accounts.held(playerId) : undefined
      if (account) this._refresh(account)
    }
  }

  /** @param {import('../game/accounts.js').Account} account */
  _refresh (account) {
    const playerId = account.playerId
    if (this._refreshing.has(playerId)) { this._refreshing.set(playerId, true); return }
    this._refreshing.set(playerId, false)
    const commits = account.commits
    this.store.readBalance(playerId).then((balance) => {
      if (balance === null || account.commits !== commits || balance === account.balance) return
      this.stats.refreshed++
      this.onBalanceChanged(account, balance)
    }, (error) => this.log.warn({ err: error, player: playerId }, 'could not re-read a balance')).finally(() => {
      const again = this._refreshing.get(playerId)
      this._refreshing.delete(playerId)
      if (again) this._refresh(account)
    })
  }

  async close () {
    await closeNotices(this.subscriber)
  }
}
