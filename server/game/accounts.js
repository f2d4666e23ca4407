import { TokenBucket } from '../limits/token-bucket.js'
import { gameError } from '../errors.js'

/**
 * A player's money and fairness state while the server works with it.
 * `balance` is the committed balance (what the database holds once every
 * queued batch is written); `reserved` is the sum of bets accepted but not
 * yet committed, so `available` can never promise credits twice. Credits
 * become available when their settlement commits, never before.
 */
export class Account {
  /**
   * @param {{ playerId: string, balance: number, clientSeed: string, createdAt: number,
   *   seed: { id: string, seed: string, hash: string, nextNonce: number } }} state
   * @param {{ dropRate: number, dropBurst: number, joinRate: number }} limits
   */
  constructor (state, limits) {
    this.playerId = state.playerId
    this.balance = state.balance
    this.reserved = 0
    this.clientSeed = state.clientSeed
    this.createdAt = state.createdAt
    /** The active server seed; `nextNonce` is taken (and never given back) when a drop is accepted. */
    this.seed = state.seed
    /** Rotations of the server seed asked for and not yet answered: drops wait for them (E_SEED_ROTATING). */
    this.seedRotations = 0
    this.dropLimiter = new TokenBucket({ rate: limits.dropRate, burst: limits.dropBurst })
    /** Batches for this player committed by this process: a balance re-read from another process's notice is stale if this moved meanwhile. */
    this.commits = 0
    this.joinLimiter = new TokenBucket({ rate: limits.joinRate, burst: 2 * limits.joinRate })
    /** @type {Set<import('../realtime/connection.js').Connection>} */
    this.connections = new Set()
    /** Reasons to keep this object in memory: connections, requests, drops in flight. */
    this.holds = 0
  }

  get available () { return this.balance - this.reserved }
}

/**
 * The one in-memory Account per player. Accounts are loaded on first use
 * and kept while anything holds them (a connection, an HTTP request, a drop
 * in flight or being written), so two copies of one player's balance can
 * never exist in the process. (Clustered, other processes hold copies too:
 * the shared ledger decides every balance, and cluster/balance-sync.js
 * refreshes this one when another process changes it.)
 */
export class AccountBook {
  /** @param {{ store: any, limits: { dropRate: number, dropBurst: number, joinRate: number } }} options */
  constructor ({ store, limits }) {
    this.store = store
    this.limits = limits
    /** @type {Map<string, Account>} */
    this.accounts = new Map()
    this.loading = new Map()
  }

  /**
   * Loads (or finds) a player's account and holds it. Release it when done.
   * @param {string} playerId
   * @returns {Promise<Account | null>} null if the player does not exist
   */
  async acquire (playerId) {
    const cached = this.accounts.get(playerId)
    if (cached) { cached.holds++; return cached }
    let loading = this.loading.get(playerId)
    if (!loading) {
      loading = this.store.loadAccount(playerId).finally(() => this.loading.delete(playerId))
      this.loading.set(playerId, loading)
    }
    const state = await loading
    if (!state) return null
    // Everyone awaiting the same load resumes here in turn: the first creates the account.
    let account = this.accounts.get(playerId)
    if (!account) this.accounts.set(playerId, (account = new Account(state, this.limits)))
    account.holds++
    return account
  }

  /** The player's account if this process holds it in memory (never loads it). @param {string} playerId @returns {Account | undefined} */
  held (playerId) {
    return this.accounts.get(playerId)
  }

  /** Adds a hold on an account already in memory. @param {Account} account */
  retain (account) {
    account.holds++
  }

  /** @param {Account} account */
  release (account) {
    if (account.holds <= 0) throw new Error(`account ${account.playerId} released more often than held`)
    if (--account.holds === 0 && this.accounts.get(account.playerId) === account) this.accounts.delete(account.playerId)
  }

  /**
   * Runs `work` with the player's account held, released after.
   * @template T
   * @param {string} playerId @param {(account: Account) => T | Promise<T>} work
   * @returns {Promise<T>} @throws GameError E_UNAUTHORIZED for a player the ledger does not have
   */
  async withAccount (playerId, work) {
    const account = await this.acquire(playerId)
    if (!account) throw gameError('E_UNAUTHORIZED', 'unknown player')
    try {
      return await work(account)
    } finally {
      this.release(account)
    }
  }

  get size () { return this.accounts.size }
}
