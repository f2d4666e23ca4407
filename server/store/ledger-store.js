/**
 * The ledger's contract: what every store (SQLite, PostgreSQL, and the
 * cluster's shared PostgreSQL ledger) promises the game. The game calls only
 * these methods; tests/server/store-contract.test.js runs the same checks
 * against every implementation. Money in the ledger is integer
 * milli-credits; the records it returns are the API's (records.js).
 *
 * @typedef {object} NewPlayer
 * @property {string} id @property {string} tokenHash SHA-256 of the session token
 * @property {number} balance milli-credits @property {string} clientSeed @property {number} createdAt ms
 * @property {{ id: string, seed: string, hash: string }} seed the first active server seed
 *
 * @typedef {object} LoadedAccount
 * @property {string} playerId @property {number} balance milli-credits, as committed
 * @property {string} clientSeed @property {number} createdAt ms
 * @property {{ id: string, seed: string, hash: string, nextNonce: number }} seed the active server seed
 *
 * @typedef {object} SeedRotation
 * @property {string} playerId @property {string} oldSeedId the active seed, revealed at `at`
 * @property {{ id: string, seed: string, hash: string }} newSeed @property {number} at ms
 *
 * @typedef {object} LedgerStore
 * @property {'sqlite' | 'postgres'} kind
 * @property {() => Promise<void>} migrate brings the schema up to date; running it again changes nothing
 * @property {(player: NewPlayer) => Promise<void>} createPlayer the player and its first seed, in one transaction
 * @property {(tokenHash: string) => Promise<string | null>} findPlayerIdByTokenHash
 * @property {(playerId: string) => Promise<LoadedAccount | null>} loadAccount
 * @property {(batch: import('./records.js').LedgerBatch) => Promise<import('../game/money.js').CommitOutcome>} commitBatch
 *   one transaction: new drops (their bets debited; each its nonce's record), settlements (payouts credited), client seeds;
 *   a drop refused by the ledger is in `rejected` and nothing of it is written; a settlement of a drop that
 *   is not in flight is never credited (it is missing from `settled`, or the whole batch is refused with an
 *   error and nothing is written); returns every touched player's committed balance
 * @property {(rotation: SeedRotation) => Promise<void>} rotateSeed reveals the old seed and activates the new one, in one transaction
 * @property {(id: number) => Promise<object | null>} getDrop a drop record, with `serverSeed` only once its seed is revealed
 * @property {(id: number) => Promise<string | null>} getServerSeedOfDrop the seed behind a drop, revealed or not: the operator's checks only
 * @property {(filter: import('./drop-filter.js').DropFilter & { limit: number }) => Promise<object[]>} listDrops newest first
 * @property {(filter: import('./drop-filter.js').DropFilter) => AsyncIterable<object>} iterateDrops oldest first, every match (export)
 * @property {() => Promise<object[]>} listInFlightDrops every drop not yet settled, by id
 * @property {(playerId: string) => Promise<object[]>} listSeeds newest first; a seed's value only once revealed
 * @property {(room: string, engineVersion: string) => Promise<object>} roomStats settled drops by bucket, and how many are in flight
 * @property {() => Promise<number>} maxDropId 0 for an empty ledger
 * @property {() => Promise<void>} close waits for writes in progress
 */

export {}
