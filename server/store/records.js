import { toCredits, toMilli } from '../../protocol/payout.js'

/**
 * Maps database rows (snake_case, the same from both stores once numbers are
 * parsed) to the records the API returns, and describes what the ledger
 * writes. The drop row is here whole, for both SQL dialects: its columns
 * (what a new drop writes, what its settlement writes), the statements that
 * write them, and the row as the API's record.
 */

/**
 * One column of the drops table: its name, the field of the row the game
 * hands the ledger (NewDropRow, SettlementRow) and its PostgreSQL type (the
 * arrays unnest() expands).
 * @typedef {{ name: string, field: string, pgType: string }} DropColumn
 */
const column = (name, field, pgType) => Object.freeze({ name, field, pgType })

/** @type {readonly DropColumn[]} what a new drop writes; its status is 'in_flight' */
export const NEW_DROP_COLUMNS = Object.freeze([
  column('id', 'id', 'bigint'),
  column('player_id', 'playerId', 'text'),
  column('room', 'room', 'text'),
  column('rows', 'rows', 'smallint'),
  column('risk', 'risk', 'text'),
  column('engine_version', 'engineVersion', 'text'),
  column('server_seed_id', 'serverSeedId', 'text'),
  column('server_seed_hash', 'serverSeedHash', 'text'),
  column('client_seed', 'clientSeed', 'text'),
  column('nonce', 'nonce', 'bigint'),
  column('drop_seed', 'dropSeed', 'text'),
  column('bet', 'bet', 'bigint'),
  column('payout_rule', 'payoutRule', 'smallint'),
  column('start_tick', 'startTick', 'bigint'),
  column('created_at', 'createdAt', 'bigint')
])

/** @type {readonly DropColumn[]} what a landing writes into its drop's row (found by `id`); its status becomes 'settled' */
export const SETTLEMENT_COLUMNS = Object.freeze([
  column('bucket', 'bucket', 'smallint'),
  column('multiplier', 'multiplier', 'float8'),
  column('payout', 'payout', 'bigint'),
  column('ticks', 'ticks', 'integer'),
  column('state_hash', 'stateHash', 'text'),
  column('settled_at', 'settledAt', 'bigint')
])

const names = (columns) => columns.map((c) => c.name).join(', ')
const NEW_DROP_NAMES = names(NEW_DROP_COLUMNS)
const SETTLED_ID = column('id', 'id', 'bigint')

/** Settled drops added to their room's totals by bucket (room_buckets, migration 3): a row per room, engine version and bucket, its counts summed. */
const ROOM_BUCKET_INSERT = 'INSERT INTO room_buckets (room, engine_version, bucket, settled, bet, payout)'
const ROOM_BUCKET_ADD = `ON CONFLICT (room, engine_version, bucket) DO UPDATE SET settled = room_buckets.settled + excluded.settled,
      bet = room_buckets.bet + excluded.bet, payout = room_buckets.payout + excluded.payout`

/**
 * The statements writing a drop's row, in each dialect. SQLite binds one
 * row at a time (newDropValues, settlementValues); PostgreSQL takes a whole
 * batch as one array per column (newDropArrays, settlementArrays) through
 * unnest(). A settlement changes only a row still in flight, and adds the
 * drop to its room's totals (room_buckets) in the same transaction: SQLite
 * with `countSettled` run after each `settle` that changed its row, given
 * the drop's id; PostgreSQL's `settle` does both and returns the drops it
 * settled (id, player_id, payout). The caller counts the rows settled
 * (SQLite: `changes`; PostgreSQL: `rowCount`, or the rows returned).
 */
export const DROP_SQL = Object.freeze({
  sqlite: Object.freeze({
    insert: `INSERT INTO drops (${NEW_DROP_NAMES}, status) VALUES (${NEW_DROP_COLUMNS.map(() => '?').join(', ')}, 'in_flight')`,
    settle: `UPDATE drops SET status = 'settled', ${SETTLEMENT_COLUMNS.map((c) => `${c.name} = ?`).join(', ')}
      WHERE id = ? AND status = 'in_flight'`,
    // (The WHERE also keeps SQLite from reading ON CONFLICT as part of the SELECT: https://sqlite.org/lang_upsert.html.)
    countSettled: `${ROOM_BUCKET_INSERT} SELECT room, engine_version, bucket, 1, bet, payout FROM drops WHERE id = ? AND status = 'settled'
      ${ROOM_BUCKET_ADD}`
  }),
  postgres: Object.freeze({
    insert: `INSERT INTO drops (${NEW_DROP_NAMES}, status)
      SELECT ${NEW_DROP_NAMES}, 'in_flight' FROM ${unnest(NEW_DROP_COLUMNS, 't')}`,
    // Totals in key order, so two transactions adding to the same rooms take their row locks in one order.
    settle: `WITH settled AS (
        UPDATE drops AS d SET status = 'settled', ${SETTLEMENT_COLUMNS.map((c) => `${c.name} = s.${c.name}`).join(', ')}
        FROM ${unnest([SETTLED_ID, ...SETTLEMENT_COLUMNS], 's')}
        WHERE d.id = s.id AND d.status = 'in_flight'
        RETURNING d.id, d.player_id, d.payout, d.room, d.engine_version, d.bucket, d.bet
      ), counted AS (
        ${ROOM_BUCKET_INSERT}
        SELECT room, engine_version, bucket, COUNT(*), SUM(bet), SUM(payout) FROM settled
        GROUP BY room, engine_version, bucket ORDER BY room, engine_version, bucket
        ${ROOM_BUCKET_ADD}
      )
      SELECT id, player_id, payout FROM settled`
  })
})

/**
 * A room's totals by bucket for one engine version, in bucket order
 * (room_buckets), and its drops in flight, read through the
 * drops_in_flight partial index (few rows, whatever the room's history;
 * SQLite is told so: it would pick drops_room_id and walk every drop of
 * the room).
 */
export const ROOM_STATS_SQL = Object.freeze({ sqlite: roomStatsSql('?', '?', 'INDEXED BY drops_in_flight'), postgres: roomStatsSql('$1', '$2', '') })

/** ROOM_STATS_SQL with a dialect's parameters for the room and the engine version, and its index hint. */
function roomStatsSql (room, engineVersion, inFlightIndex) {
  return Object.freeze({
    buckets: `SELECT bucket, settled AS count, bet, payout FROM room_buckets WHERE room = ${room} AND engine_version = ${engineVersion} ORDER BY bucket`,
    inFlight: `SELECT COUNT(*) AS n FROM drops ${inFlightIndex} WHERE status = 'in_flight' AND room = ${room} AND engine_version = ${engineVersion}`
  })
}

/** `unnest($1::bigint[], …) AS alias (name, …)`: a table of the columns from one array parameter each. */
function unnest (columns, alias) {
  return `unnest(${columns.map((c, i) => `$${i + 1}::${c.pgType}[]`).join(', ')}) AS ${alias} (${names(columns)})`
}

/** A new drop's values in NEW_DROP_COLUMNS' order (DROP_SQL.sqlite.insert). @param {NewDropRow} drop */
export function newDropValues (drop) {
  return NEW_DROP_COLUMNS.map((c) => drop[c.field])
}

/** A settlement's values, then its drop's id (DROP_SQL.sqlite.settle). @param {SettlementRow} settlement */
export function settlementValues (settlement) {
  const values = SETTLEMENT_COLUMNS.map((c) => settlement[c.field])
  values.push(settlement.id)
  return values
}

/** New drops as one array per column (DROP_SQL.postgres.insert). @param {NewDropRow[]} drops */
export function newDropArrays (drops) {
  return NEW_DROP_COLUMNS.map((c) => drops.map((drop) => drop[c.field]))
}

/** Settlements as their ids, then one array per column (DROP_SQL.postgres.settle). @param {SettlementRow[]} settlements */
export function settlementArrays (settlements) {
  return [SETTLED_ID, ...SETTLEMENT_COLUMNS].map((c) => settlements.map((s) => s[c.field]))
}

/**
 * A `drops` row as the API returns it: every column but server_seed_id (the
 * seed is named by its hash), money in credits, times as ISO strings.
 * `revealed_server_seed` is only ever selected for seeds that have been
 * revealed.
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

/**
 * A server seed's next nonce, as the ledger knows it: one past the highest
 * nonce of its recorded drops (UNIQUE (server_seed_id, nonce) makes that a
 * single index lookup), or its `next_nonce` column where that is higher (a
 * retired seed's final count, a cluster's reserved blocks:
 * cluster/shared-ledger.js). Batches do not write the column: a drop's row
 * is its nonce's record, and a per-batch update of each seed's row was a
 * write at a random place of the file per drop (loadtest/RESULTS.md). Over
 * `server_seeds AS s`, in each dialect.
 */
export const NEXT_NONCE_SQL = Object.freeze({
  sqlite: 'MAX(s.next_nonce, COALESCE((SELECT MAX(d.nonce) + 1 FROM drops d WHERE d.server_seed_id = s.id), 0))',
  postgres: 'GREATEST(s.next_nonce, COALESCE((SELECT MAX(d.nonce) + 1 FROM drops d WHERE d.server_seed_id = s.id), 0))'
})

/** Columns of a drop plus its server seed when (and only when) revealed. */
export const DROP_COLUMNS_WITH_REVEALED_SEED = `d.*, CASE WHEN s.revealed_at IS NULL THEN NULL ELSE s.seed END AS revealed_server_seed`

/**
 * Drops per page of an export (both stores' iterateDrops). Each page lands
 * on the event loop whole: PostgreSQL's rows parsed by pg, SQLite's copied
 * from its reader thread. Exporting a seed of 125,500 drops from
 * PostgreSQL, the event loop's longest pause was 7.7–8.4 ms at 1,000 a
 * page, 3.7–5.4 ms at 250, as long as a listing's page of 100
 * (bench/ledger-reads.js --ledger postgres).
 */
export const EXPORT_PAGE_DROPS = 250

/**
 * Every drop an export matches, oldest first, read a page at a time: each
 * page the next `pageSize` drops after the last one read (both stores'
 * iterateDrops; drop-pages.js says in which order).
 * @param {(afterId: number | undefined) => Promise<object[]>} readPage drop records, at most `pageSize`; the first page's cursor is undefined
 * @param {number} pageSize
 */
export async function * dropsInPages (readPage, pageSize) {
  let afterId
  for (;;) {
    const drops = await readPage(afterId)
    yield * drops
    if (drops.length < pageSize) return
    afterId = drops[drops.length - 1].id
  }
}

/**
 * @typedef {object} NewDropRow what the ledger writes when a drop is accepted (NEW_DROP_COLUMNS)
 * @property {number} id @property {string} playerId @property {string} room
 * @property {number} rows @property {string} risk @property {string} engineVersion
 * @property {string} serverSeedId @property {string} serverSeedHash
 * @property {string} clientSeed @property {number} nonce @property {string} dropSeed
 * @property {number} bet whole credits @property {number} payoutRule protocol/payout.js
 * @property {number} startTick @property {number} createdAt ms
 */

/**
 * @typedef {object} SettlementRow what the ledger writes when a drop lands (SETTLEMENT_COLUMNS, by `id`)
 * @property {number} id @property {number} bucket @property {number} multiplier
 * @property {number} payout milli-credits @property {number} ticks @property {string} stateHash
 * @property {number} settledAt ms
 */

/**
 * @typedef {object} LedgerBatch one transaction: everything one tick changed
 * @property {NewDropRow[]} drops
 * @property {SettlementRow[]} settlements
 * @property {{ playerId: string, delta: number }[]} balances net change per player, milli-credits
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
