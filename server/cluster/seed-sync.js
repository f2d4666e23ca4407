import { subscribeToNotices, closeNotices } from './notice-channel.js'

/** Redis channel on which a process announces a player's server seed rotation. */
export const SEED_CHANNEL = 'plinko:seeds'
/** Redis channel on which the others answer once they have switched. */
export const SEED_ACK_CHANNEL = 'plinko:seeds:ack'
/** A rotation is answered after this long at the most, even if some process did not confirm. */
export const SEED_ACK_TIMEOUT_MS = 1000

/**
 * Keeps the server seed of the accounts this process holds current when
 * another process rotates it (one player with tabs on two workers). The
 * rotating process publishes the player's id and the new seed's; each other
 * process that holds the account re-reads its active seed from PostgreSQL
 * (reserving a block of its nonces), then confirms; the rotation is answered
 * once every process subscribed has confirmed (or after
 * SEED_ACK_TIMEOUT_MS), so the next drop anywhere uses the new seed and
 * every `welcome` and /api/me shows the new commitment. A drop the shared
 * ledger still refuses for a revealed seed (a notice lost with Redis) makes
 * the account re-read its seed too (`refresh`), so a player is never locked
 * out. Seeds are never decided here: the shared ledger's active flag is.
 */
export class SeedSync {
  /**
   * @param {object} options
   * @param {import('ioredis').Redis} options.redis the process's connection (publishing); a duplicate subscribes
   * @param {string} options.nodeId
   * @param {{ held: (playerId: string) => import('../game/accounts.js').Account | undefined }} options.accounts the account book
   * @param {{ loadAccount: (playerId: string) => Promise<{ seed: { id: string, seed: string, hash: string, nextNonce: number } } | null> }} options.store
   * @param {import('pino').Logger} options.log
   */
  constructor ({ redis, nodeId, accounts, store, log }) {
    this.redis = redis
    this.nodeId = nodeId
    this.accounts = accounts
    this.store = store
    this.log = log
    this.subscriber = null
    this._sequence = 0
    /** @type {Map<string, { confirmed: number, needed: number, resolve: () => void }>} rotations announced here, by notice id */
    this._waiting = new Map()
    /** @type {Map<string, Promise<void>>} re-reads in progress, by player */
    this._refreshing = new Map()
    this.stats = { received: 0, switched: 0, unconfirmed: 0 }
  }

  async start () {
    this.subscriber = await subscribeToNotices({
      redis: this.redis,
      channels: [SEED_CHANNEL, SEED_ACK_CHANNEL],
      what: 'seed notices',
      log: this.log,
      onNotice: (channel, notice) => {
        if (notice.node === this.nodeId) return
        if (channel === SEED_CHANNEL) this._received(notice)
        else if (channel === SEED_ACK_CHANNEL) this._confirmed(notice)
      }
    })
  }

  /**
   * This process rotated the player's seed (committed): resolves once every
   * other process has switched, or after SEED_ACK_TIMEOUT_MS; never throws.
   * @param {string} playerId @param {string} seedId the new active seed
   */
  async rotated (playerId, seedId) {
    const id = `${this.nodeId}:${++this._sequence}`
    let timer
    const waiter = { confirmed: 0, needed: Infinity, resolve: () => {} }
    const confirmed = new Promise((resolve) => { waiter.resolve = resolve })
    this._waiting.set(id, waiter)
    const announce = this.redis.publish(SEED_CHANNEL, JSON.stringify({ node: this.nodeId, id, player: playerId, seed: seedId })).then((receivers) => {
      // Every subscribed process received it, this one's subscriber included.
      waiter.needed = receivers - 1
      if (waiter.confirmed >= waiter.needed) waiter.resolve()
      return confirmed
    })
    const timedOut = new Promise((resolve) => { timer = setTimeout(() => resolve('timeout'), SEED_ACK_TIMEOUT_MS) })
    try {
      const outcome = await Promise.race([announce, timedOut])
      if (outcome === 'timeout') {
        this.stats.unconfirmed++
        this.log.warn({ player: playerId, confirmed: waiter.confirmed, needed: waiter.needed }, 'seed rotation not confirmed by every process in time; they switch on their next refused drop')
      }
    } catch (error) {
      this.log.warn({ err: error, player: playerId }, 'could not announce a seed rotation')
    } finally {
      clearTimeout(timer)
      this._waiting.delete(id)
    }
  }

  /**
   * Re-reads the account's active seed from the shared ledger (once at a
   * time per player). @param {import('../game/accounts.js').Account} account
   * @param {string} [seedId] the seed it should become: nothing to do if it is already
   */
  refresh (account, seedId) {
    if (seedId !== undefined && account.seed.id === seedId) return Promise.resolve()
    const playerId = account.playerId
    let refreshing = this._refreshing.get(playerId)
    if (refreshing) return refreshing.then(() => this.refresh(account, seedId))
    refreshing = this.store.loadAccount(playerId).then((state) => {
      if (!state || state.seed.id === account.seed.id) return
      account.seed = state.seed
      this.stats.switched++
    }, (error) => this.log.warn({ err: error, player: playerId }, 'could not re-read a server seed')).finally(() => {
      this._refreshing.delete(playerId)
    })
    this._refreshing.set(playerId, refreshing)
    return refreshing
  }

  _received (notice) {
    if (typeof notice.player !== 'string' || typeof notice.id !== 'string') return
    this.stats.received++
    const account = this.accounts.held(notice.player)
    const switched = account ? this.refresh(account, typeof notice.seed === 'string' ? notice.seed : undefined) : Promise.resolve()
    switched.then(() => this.redis.publish(SEED_ACK_CHANNEL, JSON.stringify({ node: this.nodeId, id: notice.id })))
      .catch((error) => this.log.warn({ err: error }, 'could not confirm a seed rotation'))
  }

  _confirmed (notice) {
    const waiter = typeof notice.id === 'string' ? this._waiting.get(notice.id) : undefined
    if (!waiter) return
    if (++waiter.confirmed >= waiter.needed) waiter.resolve()
  }

  async close () {
    await closeNotices(this.subscriber)
  }
}
