import fs from 'node:fs'
import path from 'node:path'
import Database from 'better-sqlite3'
import { MIGRATIONS, MIGRATIONS_TABLE } from './migrations.js'
import { toDropRecord, accountFromRow, seedFromRow, statsFromRows, DROP_COLUMNS_WITH_REVEALED_SEED } from './records.js'
import { dropFilterSql } from './drop-filter.js'

/**
 * The ledger on SQLite (better-sqlite3): WAL journal with synchronous=FULL,
 * so a committed transaction survives a power cut. better-sqlite3 is
 * synchronous; the methods are async only to share one interface with the
 * PostgreSQL store. A commit blocks the event loop for its fsync (about
 * 0.3 ms here); one commit per tick keeps that small.
 */
export class SqliteStore {
  /** @param {{ file: string }} options file path or ':memory:' */
  constructor ({ file }) {
    if (file !== ':memory:') fs.mkdirSync(path.dirname(file), { recursive: true })
    this.kind = 'sqlite'
    this.db = new Database(file)
    this.db.pragma('journal_mode = WAL')
    this.db.pragma('synchronous = FULL')
    this.db.pragma('foreign_keys = ON')
    this.db.pragma('busy_timeout = 5000')
    this._statements = new Map()
  }

  /** Cached prepared statement. @param {string} sql */
  _sql (sql) {
    let statement = this._statements.get(sql)
    if (!statement) this._statements.set(sql, (statement = this.db.prepare(sql)))
    return statement
  }

  async migrate () {
    this.db.exec(MIGRATIONS_TABLE)
    const applied = new Set(this.db.prepare('SELECT version FROM schema_migrations').pluck().all())
    for (const migration of MIGRATIONS) {
      if (applied.has(migration.version)) continue
      this.db.transaction(() => {
        this.db.exec(migration.sql)
        this.db.prepare('INSERT INTO schema_migrations (version, name, applied_at) VALUES (?, ?, ?)')
          .run(migration.version, migration.name, Date.now())
      }).immediate()
    }
  }

  async createPlayer ({ id, tokenHash, balance, clientSeed, createdAt, seed }) {
    this.db.transaction(() => {
      this._sql('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES (?, ?, ?, ?, ?)')
        .run(id, tokenHash, balance, clientSeed, createdAt)
      this._insertSeed(id, seed, createdAt)
    }).immediate()
  }

  _insertSeed (playerId, seed, createdAt) {
    this._sql('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES (?, ?, ?, ?, 1, 0, ?)')
      .run(seed.id, playerId, seed.seed, seed.hash, createdAt)
  }

  async findPlayerIdByTokenHash (tokenHash) {
    return this._sql('SELECT id FROM players WHERE token_hash = ?').pluck().get(tokenHash) ?? null
  }

  async loadAccount (playerId) {
    const row = this._sql(`SELECT p.id, p.balance, p.client_seed, p.created_at,
        s.id AS seed_id, s.seed, s.hash, s.next_nonce
      FROM players p JOIN server_seeds s ON s.player_id = p.id AND s.active = 1
      WHERE p.id = ?`).get(playerId)
    return row ? accountFromRow(row) : null
  }

  /** @param {import('./drop-record.js').LedgerBatch} batch */
  async commitBatch (batch) {
    this.db.transaction(() => {
      const insert = this._sql(`INSERT INTO drops (id, player_id, room, rows, risk, engine_version, server_seed_id,
          server_seed_hash, client_seed, nonce, drop_seed, bet, start_tick, status, created_at)
        VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 'in_flight', ?)`)
      for (const d of batch.drops) {
        insert.run(d.id, d.playerId, d.room, d.rows, d.risk, d.engineVersion, d.serverSeedId,
          d.serverSeedHash, d.clientSeed, d.nonce, d.dropSeed, d.bet, d.startTick, d.createdAt)
      }
      const settle = this._sql(`UPDATE drops SET status = 'settled', bucket = ?, multiplier = ?, payout = ?,
          ticks = ?, state_hash = ?, settled_at = ? WHERE id = ? AND status = 'in_flight'`)
      for (const s of batch.settlements) {
        const { changes } = settle.run(s.bucket, s.multiplier, s.payout, s.ticks, s.stateHash, s.settledAt, s.id)
        if (changes !== 1) throw new Error(`drop ${s.id} is not in flight; refusing to settle it twice`)
      }
      const credit = this._sql('UPDATE players SET balance = balance + ? WHERE id = ?')
      for (const b of batch.balances) {
        if (credit.run(b.delta, b.playerId).changes !== 1) throw new Error(`no player ${b.playerId}`)
      }
      const nonce = this._sql('UPDATE server_seeds SET next_nonce = MAX(next_nonce, ?) WHERE id = ?')
      for (const n of batch.nonces) nonce.run(n.nextNonce, n.seedId)
      const clientSeed = this._sql('UPDATE players SET client_seed = ? WHERE id = ?')
      for (const c of batch.clientSeeds) clientSeed.run(c.clientSeed, c.playerId)
    }).immediate()
  }

  async rotateSeed ({ playerId, oldSeedId, newSeed, at }) {
    this.db.transaction(() => {
      const { changes } = this._sql('UPDATE server_seeds SET active = 0, revealed_at = ? WHERE id = ? AND player_id = ? AND active = 1')
        .run(at, oldSeedId, playerId)
      if (changes !== 1) throw new Error(`seed ${oldSeedId} is not the active seed of ${playerId}`)
      this._insertSeed(playerId, newSeed, at)
    }).immediate()
  }

  async getDrop (id) {
    const row = this._sql(`SELECT ${DROP_COLUMNS_WITH_REVEALED_SEED} FROM drops d
      JOIN server_seeds s ON s.id = d.server_seed_id WHERE d.id = ?`).get(id)
    return row ? toDropRecord(row) : null
  }

  /** The server seed behind a drop, revealed or not: for the operator's checks only, never returned to anyone. */
  async getServerSeedOfDrop (id) {
    return this._sql('SELECT s.seed FROM drops d JOIN server_seeds s ON s.id = d.server_seed_id WHERE d.id = ?').pluck().get(id) ?? null
  }

  async listDrops (filter) {
    const { where, params } = dropFilterSql(filter, () => '?')
    const rows = this.db.prepare(`SELECT ${DROP_COLUMNS_WITH_REVEALED_SEED} FROM drops d
      JOIN server_seeds s ON s.id = d.server_seed_id ${where} ORDER BY d.id DESC LIMIT ?`).all(...params, filter.limit)
    return rows.map(toDropRecord)
  }

  async * iterateDrops (filter, pageSize = 1000) {
    let afterId = 0
    for (;;) {
      const { where, params } = dropFilterSql({ ...filter, afterId }, () => '?')
      const rows = this.db.prepare(`SELECT ${DROP_COLUMNS_WITH_REVEALED_SEED} FROM drops d
        JOIN server_seeds s ON s.id = d.server_seed_id ${where} ORDER BY d.id LIMIT ?`).all(...params, pageSize)
      for (const row of rows) yield toDropRecord(row)
      if (rows.length < pageSize) return
      afterId = Number(rows[rows.length - 1].id)
    }
  }

  async listInFlightDrops () {
    return this._sql("SELECT * FROM drops WHERE status = 'in_flight' ORDER BY id").all().map(toDropRecord)
  }

  async listSeeds (playerId) {
    return this._sql(`SELECT id, hash, active, next_nonce, created_at, revealed_at,
        CASE WHEN revealed_at IS NULL THEN NULL ELSE seed END AS revealed_seed
      FROM server_seeds WHERE player_id = ? ORDER BY created_at DESC, id`).all(playerId).map(seedFromRow)
  }

  async roomStats (room) {
    const buckets = this._sql(`SELECT bucket, COUNT(*) AS count, SUM(bet) AS bet, SUM(payout) AS payout
      FROM drops WHERE room = ? AND status = 'settled' GROUP BY bucket ORDER BY bucket`).all(room)
    const inFlight = this._sql("SELECT COUNT(*) FROM drops WHERE room = ? AND status = 'in_flight'").pluck().get(room)
    return statsFromRows(buckets, inFlight)
  }

  async maxDropId () {
    return Number(this._sql('SELECT COALESCE(MAX(id), 0) FROM drops').pluck().get())
  }

  async close () {
    if (this.db.open) this.db.close()
  }
}
