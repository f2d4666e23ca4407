/**
 * Notices about accounts between processes (chosen once at start in
 * modes.js): what this process changed is announced, what others changed
 * reaches the accounts held here. Never decides a balance or a seed (the
 * ledger does).
 *
 * - LocalAccountFeed (local-account-feed.js): alone, nobody else changes an
 *   account; every call is a no-op.
 * - ClusterAccountFeed (../cluster/cluster-account-feed.js): Redis pub/sub;
 *   a notice from another process re-reads the account's committed balance
 *   (told to its connections) or active seed from the shared ledger.
 *
 * @typedef {object} AccountFeed
 * @property {(services: FeedServices) => Promise<void>} start
 * @property {(playerIds: Iterable<string>) => void} balancesCommitted these players' balances changed in the ledger
 * @property {(account: import('../game/accounts.js').Account) => Promise<void>} seedRotated
 *   this process rotated the account's server seed (committed): resolves once every other process holding it uses the new one
 * @property {(account: import('../game/accounts.js').Account) => Promise<void>} seedOutdated
 *   the ledger refused a drop on a seed no longer active (E_SEED_ROTATED): re-reads the account's active seed (never rejects)
 * @property {() => Promise<void>} close
 *
 * @typedef {object} FeedServices
 * @property {import('../game/accounts.js').AccountBook} accounts whose held accounts (`held`) other processes' seed rotations switch
 * @property {(account: import('../game/accounts.js').Account, balance: number) => void} onBalanceChanged
 *   another process committed this balance (milli-credits) for an account held here
 */
export {}
