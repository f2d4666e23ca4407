import pg from 'pg'
import { MIGRATIONS, MIGRATIONS_TABLE } from './migrations.js'
import { toDropRecord, accountFromRow, seedFromRow, statsFromRows, ROOM_STATS_SQL, wholeBatchCommitted, DROP_COLUMNS_WITH_REVEALED_SEED, EXPORT_PAGE_DROPS, dropsInPages, DROP_SQL, NEXT_NONCE_SQL, newDropArrays, settlementArrays } from './records.js'
import { dropsPage, driveDropsPageAsync, listedPage } from './drop-pages.js'

const INT8_OID = 20
const NUMERIC_OID = 1700
/** Any number stable for this app: serialises migrations across processes. */
const MIGRATION_LOCK = 0x706c696e6b6f

/**
 * BIGINT and NUMERIC (what SUM returns) as JS numbers: credits stay far below
 * 2^53. Set per pool, so other users of `pg` in the process are unaffected.
 */
const types = {
  getTypeParser (oid, format) {
    if (oid === INT8_OID || oid === NUMERIC_OID) return (value) => (value === null ? null : Number(value))
    return pg.types.getTypeParser(oid, format)
  }
}

/** Connections the listings of drops have, apart from the store's pool (PostgresStore). */
export const LISTING_POOL_SIZE = 2

/**
 * The ledger on PostgreSQL through a `pg` pool, with the same schema and
 * interface as the SQLite store. A batch is a handful of statements whatever
 * its size: rows travel as arrays and are expanded by unnest().
 * @implements {import('./ledger-store.js').LedgerStore}
 */
export class PostgresStore {
  /** @param {{ url: string, poolSize?: number }} options */
  constructor ({ url, poolSize = 10 }) {
    this.kind = 'postgres'
    this.pool = new pg.Pool({ connectionString: url, max: poolSize, types })
    // The listings of drops (an operator's, however broad; a player's history; an export's
    // pages) on connections of their own: however many run at once, and however long, they
    // never take the connection a tick's commit waits for.
    this.listingPool = new pg.Pool({ connectionString: url, max: LISTING_POOL_SIZE, types })
    // An idle client losing its connection must not crash the process; the next query reconnects.
    this.pool.on('error', () => {})
    this.listingPool.on('error', () => {})
  }

  /** Runs `work(client)` inside BEGIN/COMMIT on one pooled connection. */
  async _transaction (work) {
    const client = await this.pool.connect()
    try {
      await client.query('BEGIN')
      const result = await work(client)
      await client.query('COMMIT')
      return result
    } catch (error) {
      await client.query('ROLLBACK').catch(() => {})
      throw error
    } finally {
      client.release()
    }
  }

  async migrate () {
    await this._transaction(async (client) => {
      await client.query('SELECT pg_advisory_xact_lock($1)', [MIGRATION_LOCK])
      await client.query(MIGRATIONS_TABLE)
      const { rows } = await client.query('SELECT version FROM schema_migrations')
      const applied = new Set(rows.map((row) => Number(row.version)))
      for (const migration of MIGRATIONS) {
        if (applied.has(migration.version)) continue
        await client.query(migration.sql)
        await client.query('INSERT INTO schema_migrations (version, name, applied_at) VALUES ($1, $2, $3)',
          [migration.version, migration.name, Date.now()])
      }
    })
  }

  async createPlayer ({ id, tokenHash, balance, clientSeed, createdAt, seed }) {
    await this._transaction(async (client) => {
      await client.query('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES ($1, $2, $3, $4, $5)',
        [id, tokenHash, balance, clientSeed, createdAt])
      await insertSeed(client, id, seed, createdAt)
    })
  }

  async findPlayerIdByTokenHash (tokenHash) {
    const { rows } = await this.pool.query('SELECT id FROM players WHERE token_hash = $1', [tokenHash])
    return rows[0]?.id ?? null
  }

  async loadAccount (playerId) {
    const { rows } = await this.pool.query(`SELECT p.id, p.balance, p.client_seed, p.created_at,
        s.id AS seed_id, s.seed, s.hash, ${NEXT_NONCE_SQL.postgres} AS next_nonce
      FROM players p JOIN server_seeds s ON s.player_id = p.id AND s.active = 1
      WHERE p.id = $1`, [playerId])
    return rows[0] ? accountFromRow(rows[0]) : null
  }

  /**
   * Writes the batch whole or not at all; returns what it committed (one
   * process owns this ledger, so nothing is refused) and the touched
   * players' balances as committed.
   * @param {import('./records.js').LedgerBatch} batch @returns {Promise<import('../game/money.js').CommitOutcome>}
   */
  async commitBatch (batch) {
    return this._transaction(async (client) => {
      const drops = batch.drops
      if (drops.length > 0) {
        await insertInFlightDrops(client, drops)
      }
      const settlements = batch.settlements
      if (settlements.length > 0) {
        const { rowCount } = await client.query(DROP_SQL.postgres.settle, settlementArrays(settlements))
        if (rowCount !== settlements.length) throw new Error('a drop in the batch is not in flight; refusing to settle it twice')
      }
      if (batch.balances.length > 0) {
        const { rowCount } = await client.query(`UPDATE players AS p SET balance = p.balance + b.delta
          FROM unnest($1::text[], $2::bigint[]) AS b (id, delta) WHERE p.id = b.id`,
        columns(batch.balances, ['playerId', 'delta']))
        if (rowCount !== batch.balances.length) throw new Error('a player in the batch does not exist')
      }
      if (batch.clientSeeds.length > 0) {
        await client.query(`UPDATE players AS p SET client_seed = c.client_seed
          FROM unnest($1::text[], $2::text[]) AS c (id, client_seed) WHERE p.id = c.id`,
        columns(batch.clientSeeds, ['playerId', 'clientSeed']))
      }
      const balances = new Map()
      if (batch.players?.length > 0) {
        const { rows } = await client.query('SELECT id, balance FROM players WHERE id = ANY($1::text[])', [batch.players])
        for (const row of rows) balances.set(row.id, Number(row.balance))
      }
      return wholeBatchCommitted(batch, balances)
    })
  }

  async rotateSeed ({ playerId, oldSeedId, newSeed, at }) {
    await this._transaction(async (client) => {
      // A retired seed keeps its final count: what its reveal says it was used for.
      const { rowCount } = await client.query(
        `UPDATE server_seeds AS s SET active = 0, revealed_at = $1, next_nonce = ${NEXT_NONCE_SQL.postgres}
          WHERE s.id = $2 AND s.player_id = $3 AND s.active = 1`,
        [at, oldSeedId, playerId])
      if (rowCount !== 1) throw new Error(`seed ${oldSeedId} is not the active seed of ${playerId}`)
      await insertSeed(client, playerId, newSeed, at)
    })
  }

  async getDrop (id) {
    const { rows } = await this.pool.query(`SELECT ${DROP_COLUMNS_WITH_REVEALED_SEED} FROM drops d
      JOIN server_seeds s ON s.id = d.server_seed_id WHERE d.id = $1`, [id])
    return rows[0] ? toDropRecord(rows[0]) : null
  }

  /** The server seed behind a drop, revealed or not: for the operator's checks only, never returned to anyone. */
  async getServerSeedOfDrop (id) {
    const { rows } = await this.pool.query('SELECT s.seed FROM drops d JOIN server_seeds s ON s.id = d.server_seed_id WHERE d.id = $1', [id])
    return rows[0]?.seed ?? null
  }

  async listDrops (filter) {
    return listedPage(await this._selectDrops(filter, 'DESC', filter.limit), filter.beforeId)
  }

  async * iterateDrops (filter, pageSize = EXPORT_PAGE_DROPS) {
    yield * dropsInPages(async (afterId) => listedPage(await this._selectDrops({ ...filter, afterId }, 'ASC', pageSize), afterId), pageSize)
  }

  /** A page of the drops `filter` matches (drop-pages.js), on the listing pool. */
  async _selectDrops (filter, order, limit) {
    return driveDropsPageAsync(dropsPage(filter, order, limit, 'postgres'), async (sql, params) => (await this.listingPool.query(sql, params)).rows)
  }

  async listInFlightDrops () {
    const { rows } = await this.pool.query("SELECT * FROM drops WHERE status = 'in_flight' ORDER BY id")
    return rows.map(toDropRecord)
  }

  async listSeeds (playerId) {
    const { rows } = await this.pool.query(`SELECT s.id, s.hash, s.active, ${NEXT_NONCE_SQL.postgres} AS next_nonce, s.created_at, s.revealed_at,
        CASE WHEN s.revealed_at IS NULL THEN NULL ELSE s.seed END AS revealed_seed
      FROM server_seeds s WHERE s.player_id = $1 ORDER BY s.created_at DESC, s.id`, [playerId])
    return rows.map(seedFromRow)
  }

  async roomStats (room, engineVersion) {
    const buckets = await this.pool.query(ROOM_STATS_SQL.postgres.buckets, [room, engineVersion])
    const inFlight = await this.pool.query(ROOM_STATS_SQL.postgres.inFlight, [room, engineVersion])
    return statsFromRows(buckets.rows, inFlight.rows[0].n)
  }

  async maxDropId () {
    const { rows } = await this.pool.query('SELECT COALESCE(MAX(id), 0) AS id FROM drops')
    return Number(rows[0].id)
  }

  async close () {
    if (!this.listingPool.ended) await this.listingPool.end()
    if (!this.pool.ended) await this.pool.end()
  }
}

function insertSeed (client, playerId, seed, createdAt) {
  return client.query('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES ($1, $2, $3, $4, 1, 0, $5)',
    [seed.id, playerId, seed.seed, seed.hash, createdAt])
}

/** Row objects → one array per field, for unnest(). */
export function columns (rows, fields) {
  return fields.map((field) => rows.map((row) => row[field]))
}

/**
 * Inserts new drops, status in_flight, in one statement. Shared by the
 * single-process store and the cluster's shared ledger.
 * @param {import('pg').PoolClient} client
 * @param {import('./records.js').NewDropRow[]} drops
 */
export async function insertInFlightDrops (client, drops) {
  await client.query(DROP_SQL.postgres.insert, newDropArrays(drops))
}
