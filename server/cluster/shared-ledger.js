import { PostgresStore, columns, insertInFlightDrops } from '../store/postgres-store.js'
import { gameError } from '../errors.js'
import { toDropRecord, DROP_SQL, settlementArrays } from '../store/records.js'
import { betTotals, payoutTotals } from '../game/money.js'

/** Nonces reserved per (process, seed) at a time; a reservation is never given back. */
export const NONCE_BLOCK = 100
/** Drop ids reserved per process at a time. */
export const DROP_ID_BLOCK = 10_000

/**
 * The ledger when several processes share one PostgreSQL database. It is
 * the PostgreSQL store with four changes, so that the database — not any
 * process's memory — decides every balance, nonce and drop id:
 *
 * - A batch's debits are conditional (`balance >= bets`) and its drops are
 *   recorded only if their server seed is still active (locked FOR SHARE
 *   against a concurrent rotation). A refused drop is not written and the
 *   rest of the batch commits: `commitBatch` returns which drops were
 *   refused and why (E_INSUFFICIENT_FUNDS, E_SEED_ROTATED).
 * - A settlement is written only if its drop is still in flight
 *   (`UPDATE … WHERE status = 'in_flight' RETURNING`), and only those rows
 *   are credited: two processes can never settle the same drop twice.
 * - Nonces are reserved in blocks in the database (`UPDATE server_seeds SET
 *   next_nonce = next_nonce + N … RETURNING`) when an account is loaded, its
 *   seed rotated, or its block runs low, so two processes never use the same
 *   nonce of a seed.
 * - Drop ids are reserved in blocks from one counter row.
 *
 * It only reserves: the process's sequences (cluster-sequences.js) hand the
 * numbers out, and learn of the blocks reserved with a load or a rotation
 * through `watchNonceBlocks`.
 *
 * `commitBatch` also returns every touched player's balance as committed,
 * which the arena shows instead of its cached one.
 * @implements {import('../store/ledger-store.js').LedgerStore}
 */
export class SharedLedgerStore extends PostgresStore {
  /** @param {{ url: string, poolSize?: number, nonceBlock?: number, dropIdBlock?: number }} options */
  constructor ({ nonceBlock = NONCE_BLOCK, dropIdBlock = DROP_ID_BLOCK, ...options }) {
    super(options)
    this.nonceBlock = nonceBlock
    this.dropIdBlock = dropIdBlock
    /** @type {NonceBlockWatcher | null} */
    this._nonceWatcher = null
  }

  /**
   * Who hands out the nonces this store reserves while loading an account or
   * rotating its seed (cluster-sequences.js). @param {NonceBlockWatcher} watcher
   */
  watchNonceBlocks (watcher) {
    this._nonceWatcher = watcher
  }

  async migrate () {
    await super.migrate()
    // Not a ledger migration (the single-process SQLite schema has no use for it): cluster bookkeeping.
    await this.pool.query(`CREATE TABLE IF NOT EXISTS cluster_counters (name TEXT PRIMARY KEY, value BIGINT NOT NULL)`)
      .catch((error) => { if (error.code !== '23505' && error.code !== '42P07') throw error })
  }

  // ---- drop ids -------------------------------------------------------------

  /** Reserves the next block of drop ids for this process. @returns {Promise<{ start: number, end: number }>} */
  async reserveDropIds () {
    const n = this.dropIdBlock
    // GREATEST with MAX(id): stays above ids written by a single-process run on the same database.
    const { rows } = await this.pool.query(`INSERT INTO cluster_counters (name, value)
        VALUES ('drop_id', (SELECT COALESCE(MAX(id), 0) FROM drops) + $1)
      ON CONFLICT (name) DO UPDATE SET value = GREATEST(cluster_counters.value, (SELECT COALESCE(MAX(id), 0) FROM drops)) + $1
      RETURNING value`, [n])
    const end = Number(rows[0].value) + 1
    return { start: end - n, end }
  }

  // ---- nonces ---------------------------------------------------------------

  /** Loads an account and reserves a block of its active seed's nonces. */
  async loadAccount (playerId) {
    const { rows } = await this.pool.query(`UPDATE server_seeds AS s SET next_nonce = s.next_nonce + $2
      FROM players p WHERE p.id = $1 AND s.player_id = p.id AND s.active = 1
      RETURNING p.id, p.balance, p.client_seed, p.created_at, s.id AS seed_id, s.seed, s.hash, s.next_nonce - $2 AS next_nonce`,
    [playerId, this.nonceBlock])
    if (!rows[0]) return null
    const row = rows[0]
    const start = Number(row.next_nonce)
    this._nonceWatcher?.reserved(row.seed_id, { start, end: start + this.nonceBlock })
    return {
      playerId: row.id,
      balance: Number(row.balance),
      clientSeed: row.client_seed,
      createdAt: Number(row.created_at),
      seed: { id: row.seed_id, seed: row.seed, hash: row.hash, nextNonce: start }
    }
  }

  /**
   * Reserves the seed's next block of nonces for this process, if it is still active.
   * @param {string} seedId @returns {Promise<{ start: number, end: number } | null>}
   */
  async reserveNonces (seedId) {
    const { rows } = await this.pool.query('UPDATE server_seeds SET next_nonce = next_nonce + $2 WHERE id = $1 AND active = 1 RETURNING next_nonce',
      [seedId, this.nonceBlock])
    return rows[0] ? { start: Number(rows[0].next_nonce) - this.nonceBlock, end: Number(rows[0].next_nonce) } : null
  }

  /** Rotation commits the new seed with its first block already reserved for this process. */
  async rotateSeed ({ playerId, oldSeedId, newSeed, at }) {
    await this._transaction(async (client) => {
      const { rowCount } = await client.query(
        'UPDATE server_seeds SET active = 0, revealed_at = $1 WHERE id = $2 AND player_id = $3 AND active = 1',
        [at, oldSeedId, playerId])
      if (rowCount !== 1) throw gameError('E_SEED_ROTATED', `seed ${oldSeedId} is no longer the active seed (rotated by another process); try again`)
      // Another process's drops on the old seed may have committed while this waited for the row (their FOR SHARE),
      // stamped by its clock after `at`: the seed is revealed after the last of them (none can follow: it is inactive).
      await client.query(`UPDATE server_seeds SET revealed_at = GREATEST(revealed_at,
          COALESCE((SELECT MAX(created_at) FROM drops WHERE server_seed_id = $1), 0)) WHERE id = $1`, [oldSeedId])
      await client.query('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES ($1, $2, $3, $4, 1, $5, $6)',
        [newSeed.id, playerId, newSeed.seed, newSeed.hash, this.nonceBlock, at])
    })
    this._nonceWatcher?.retired(oldSeedId)
    this._nonceWatcher?.reserved(newSeed.id, { start: 0, end: this.nonceBlock })
  }

  // ---- recovery of other processes' drops -------------------------------------

  /** Rooms that have drops in flight (any process's). @returns {Promise<string[]>} */
  async listRoomsWithDropsInFlight () {
    const { rows } = await this.pool.query("SELECT DISTINCT room FROM drops WHERE status = 'in_flight'")
    return rows.map((row) => row.room)
  }

  /** @param {string} room */
  async listInFlightDropsOfRoom (room) {
    const { rows } = await this.pool.query("SELECT * FROM drops WHERE status = 'in_flight' AND room = $1 ORDER BY id", [room])
    return rows.map(toDropRecord)
  }

  /** A player's committed balance, or null if there is no such player. @param {string} playerId */
  async readBalance (playerId) {
    const { rows } = await this.pool.query('SELECT balance FROM players WHERE id = $1', [playerId])
    return rows.length === 0 ? null : Number(rows[0].balance)
  }

  // ---- the batch ------------------------------------------------------------

  /**
   * @param {import('../store/records.js').LedgerBatch} batch (its `balances` are ignored:
   *   debits and credits are computed here from what the database accepts)
   * @returns {Promise<{ rejected: Map<number, string>, settled: Set<number>, balances: Map<string, number> }>}
   */
  async commitBatch (batch) {
    return this._transaction(async (client) => {
      const players = new Set(batch.players)
      await lockBatchRows(client, batch)
      const { accepted, rejected } = await recordDropsIfPaid(client, batch.drops)
      for (const drop of batch.drops) players.add(drop.playerId)
      const settled = await settleInFlight(client, batch.settlements, players)
      // A client seed set by a refused drop is not kept (the arena puts the old one back too).
      const acceptedPlayers = new Set(accepted.map((d) => d.playerId))
      const dropPlayers = new Set(batch.drops.map((d) => d.playerId))
      const clientSeeds = batch.clientSeeds.filter((c) => !dropPlayers.has(c.playerId) || acceptedPlayers.has(c.playerId))
      if (clientSeeds.length > 0) {
        await client.query(`UPDATE players AS p SET client_seed = c.client_seed
          FROM unnest($1::text[], $2::text[]) AS c (id, client_seed) WHERE p.id = c.id`,
        columns(clientSeeds, ['playerId', 'clientSeed']))
      }
      return { rejected, settled, balances: await committedBalances(client, players) }
    })
  }
}

/**
 * Row locks in one global order (settled drops by id, then players by id), so
 * two processes' batches wait for each other instead of deadlocking.
 * @param {import('pg').PoolClient} client @param {import('../store/records.js').LedgerBatch} batch
 */
async function lockBatchRows (client, batch) {
  const settlingIds = batch.settlements.map((s) => s.id)
  if (settlingIds.length > 0) await client.query('SELECT id FROM drops WHERE id = ANY($1::bigint[]) ORDER BY id FOR UPDATE', [settlingIds])
  await client.query(`SELECT id FROM players WHERE id = ANY($1::text[])
      OR id IN (SELECT player_id FROM drops WHERE id = ANY($2::bigint[])) ORDER BY id FOR UPDATE`,
  [[...new Set(batch.drops.map((d) => d.playerId))], settlingIds])
}

/**
 * Records the drops whose seed is still active (locked FOR SHARE against a
 * concurrent rotation) and whose player can pay for all of them: the debit is
 * conditional (`balance >= bets`). The rest are refused, nothing written.
 * @param {import('pg').PoolClient} client @param {import('../store/records.js').NewDropRow[]} drops
 * @returns {Promise<{ accepted: import('../store/records.js').NewDropRow[], rejected: Map<number, string> }>}
 */
async function recordDropsIfPaid (client, drops) {
  const rejected = new Map()
  if (drops.length === 0) return { accepted: drops, rejected }
  const seedIds = [...new Set(drops.map((d) => d.serverSeedId))]
  const { rows: active } = await client.query('SELECT id FROM server_seeds WHERE id = ANY($1::text[]) AND active = 1 FOR SHARE', [seedIds])
  const activeIds = new Set(active.map((r) => r.id))
  for (const drop of drops) if (!activeIds.has(drop.serverSeedId)) rejected.set(drop.id, 'E_SEED_ROTATED')
  let accepted = drops.filter((d) => !rejected.has(d.id))
  const totals = betTotals(accepted)
  if (totals.size > 0) {
    const { rows: debited } = await client.query(`UPDATE players AS p SET balance = p.balance - b.total
      FROM unnest($1::text[], $2::bigint[]) AS b (id, total) WHERE p.id = b.id AND p.balance >= b.total RETURNING p.id`,
    [[...totals.keys()], [...totals.values()]])
    const paid = new Set(debited.map((r) => r.id))
    for (const drop of accepted) if (!paid.has(drop.playerId)) rejected.set(drop.id, 'E_INSUFFICIENT_FUNDS')
    accepted = accepted.filter((d) => !rejected.has(d.id))
  }
  if (accepted.length > 0) await insertInFlightDrops(client, accepted)
  return { accepted, rejected }
}

/**
 * Settles the drops still in flight (`WHERE status = 'in_flight' RETURNING`)
 * and credits only those: two processes can never settle one drop twice.
 * @param {import('pg').PoolClient} client @param {import('../store/records.js').SettlementRow[]} settlements
 * @param {Set<string>} players the batch's players: the settled drops' owners are added
 * @returns {Promise<Set<number>>} the drops settled here
 */
async function settleInFlight (client, settlements, players) {
  const settled = new Set()
  if (settlements.length === 0) return settled
  const { rows } = await client.query(DROP_SQL.postgres.settle, settlementArrays(settlements))
  for (const row of rows) {
    settled.add(Number(row.id))
    players.add(row.player_id)
  }
  const credits = payoutTotals(rows.map((row) => ({ playerId: row.player_id, payout: Number(row.payout) })))
  if (credits.size > 0) {
    await client.query(`UPDATE players AS p SET balance = p.balance + c.amount
      FROM unnest($1::text[], $2::bigint[]) AS c (id, amount) WHERE p.id = c.id`,
    [[...credits.keys()], [...credits.values()]])
  }
  return settled
}

/** @param {import('pg').PoolClient} client @param {Set<string>} players @returns {Promise<Map<string, number>>} */
async function committedBalances (client, players) {
  const balances = new Map()
  if (players.size === 0) return balances
  const { rows } = await client.query('SELECT id, balance FROM players WHERE id = ANY($1::text[])', [[...players]])
  for (const row of rows) balances.set(row.id, Number(row.balance))
  return balances
}

/** Opens and migrates the shared ledger. @param {{ url: string }} database */
export async function openSharedLedger (database) {
  const store = new SharedLedgerStore({ url: database.url })
  try {
    await store.migrate()
  } catch (error) {
    await store.close().catch(() => {})
    throw error
  }
  return store
}

/**
 * @typedef {object} NonceBlockWatcher
 * @property {(seedId: string, block: { start: number, end: number }) => void} reserved
 *   a block of the seed's nonces is this process's (a load or a rotation reserved it); it replaces any earlier one
 * @property {(seedId: string) => void} retired the seed was rotated away: no more of its nonces
 */
