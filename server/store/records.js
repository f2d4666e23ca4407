import { toCredits, toMilli } from '../../protocol/payout.js'

/**
 * Maps database rows (snake_case, the same from both stores once numbers are
 * parsed) to the records the API returns, and describes what the ledger
 * writes.
 */

/**
 * A `drops` row as the API returns it. `revealed_server_seed` is only ever
 * selected for seeds that have been revealed.
 * @param {Record<string, any>} row
 */
export function toDropRecord (row) {
  const record = {
    id: Number(row.id),
    playerId: row.player_id,
    room: row.room,
    rows: Number(row.rows),
    risk: row.risk,
    engineVersion: row.engine_version,
    serverSeedHash: row.server_seed_hash,
    clientSeed: row.client_seed,
    nonce: Number(row.nonce),
    dropSeed: row.drop_seed,
    bet: Number(row.bet),
    bucket: row.bucket === null ? null : Number(row.bucket),
    multiplier: row.multiplier === null ? null : Number(row.multiplier),
    payout: row.payout === null ? null : toCredits(Number(row.payout)),
    payoutRule: Number(row.payout_rule),
    startTick: Number(row.start_tick),
    ticks: row.ticks === null ? null : Number(row.ticks),
    stateHash: row.state_hash,
    status: row.status,
    createdAt: new Date(Number(row.created_at)).toISOString(),
    settledAt: row.settled_at === null ? null : new Date(Number(row.settled_at)).toISOString()
  }
  if (row.revealed_server_seed !== undefined) record.serverSeed = row.revealed_server_seed
  return record
}

/** Columns of a drop plus its server seed when (and only when) revealed. */
export const DROP_COLUMNS_WITH_REVEALED_SEED = `d.*, CASE WHEN s.revealed_at IS NULL THEN NULL ELSE s.seed END AS revealed_server_seed`

/**
 * @typedef {object} NewDropRow what the ledger writes when a drop is accepted
 * @property {number} id @property {string} playerId @property {string} room
 * @property {number} rows @property {string} risk @property {string} engineVersion
 * @property {string} serverSeedId @property {string} serverSeedHash
 * @property {string} clientSeed @property {number} nonce @property {string} dropSeed
 * @property {number} bet whole credits @property {number} payoutRule protocol/payout.js
 * @property {number} startTick @property {number} createdAt ms
 */

/**
 * @typedef {object} SettlementRow what the ledger writes when a drop lands
 * @property {number} id @property {number} bucket @property {number} multiplier
 * @property {number} payout milli-credits @property {number} ticks @property {string} stateHash
 * @property {number} settledAt ms
 */

/**
 * @typedef {object} LedgerBatch one transaction: everything one tick changed
 * @property {NewDropRow[]} drops
 * @property {SettlementRow[]} settlements
 * @property {{ playerId: string, delta: number }[]} balances net change per player, milli-credits
 * @property {{ seedId: string, nextNonce: number }[]} nonces
 * @property {{ playerId: string, clientSeed: string }[]} clientSeeds
 * @property {string[]} [players] every player the batch touches: the store returns their committed balances
 */

/**
 * What a single-process store's commitBatch returns: the batch was written
 * whole (one process owns the ledger, so nothing is refused), with the
 * touched players' balances as committed.
 * @param {LedgerBatch} batch @param {Map<string, number>} balances
 * @returns {import('../game/money.js').CommitOutcome}
 */
export function wholeBatchCommitted (batch, balances) {
  return { rejected: new Map(), settled: new Set(batch.settlements.map((s) => s.id)), balances }
}

/** A player with its active seed, as the account book caches it. */
export function accountFromRow (row) {
  return {
    playerId: row.id,
    balance: Number(row.balance),
    clientSeed: row.client_seed,
    createdAt: Number(row.created_at),
    seed: { id: row.seed_id, seed: row.seed, hash: row.hash, nextNonce: Number(row.next_nonce) }
  }
}

/** A server seed as the player sees it: the seed itself only once revealed. */
export function seedFromRow (row) {
  return {
    id: row.id,
    serverSeedHash: row.hash,
    active: Number(row.active) === 1,
    nonce: Number(row.next_nonce),
    serverSeed: row.revealed_seed ?? null,
    createdAt: new Date(Number(row.created_at)).toISOString(),
    revealedAt: row.revealed_at === null ? null : new Date(Number(row.revealed_at)).toISOString()
  }
}

/** Per-bucket counts and totals of a room's settled drops, and its measured RTP. */
export function statsFromRows (bucketRows, inFlight) {
  // Summed in milli-credits (integers, exact), shown in credits.
  let drops = 0; let totalBet = 0; let totalPayoutMilli = 0
  const buckets = bucketRows.map((row) => {
    const count = Number(row.count); const bet = Number(row.bet); const payoutMilli = Number(row.payout)
    drops += count; totalBet += bet; totalPayoutMilli += payoutMilli
    return { bucket: Number(row.bucket), count, bet, payout: toCredits(payoutMilli) }
  })
  const totalPayout = toCredits(totalPayoutMilli)
  return { settled: drops, inFlight: Number(inFlight), totalBet, totalPayout, rtp: totalBet === 0 ? null : totalPayoutMilli / toMilli(totalBet), buckets }
}
