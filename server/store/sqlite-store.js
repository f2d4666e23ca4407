import { MIGRATIONS, MIGRATIONS_TABLE } from './migrations.js'
import { toDropRecord, accountFromRow, seedFromRow, statsFromRows, ROOM_STATS_SQL, DROP_COLUMNS_WITH_REVEALED_SEED, NEXT_NONCE_SQL, EXPORT_PAGE_DROPS, dropsInPages } from './records.js'
import { openSqliteDatabase } from './sqlite-database.js'
import { prepareWrites, immediateTransaction, WRITER_THREAD } from './sqlite-writer-thread.js'
import { prepareReads, READER_THREAD } from './sqlite-reader-thread.js'
import { SqliteThreadClient } from './sqlite-thread-client.js'
import { gameError } from '../errors.js'
import { DiskReserve, checkpointLeftoverWal } from './disk-reserve.js'
import { SqliteCheckpointer } from './sqlite-checkpoint-thread.js'
import { listedPage } from './drop-pages.js'

/**
 * The ledger on SQLite (Node's `node:sqlite`): WAL journal with synchronous=FULL,
 * so a committed transaction survives a power cut. Every write (the tick's
 * batches, new players, seed rotations: sqlite-writer-thread.js) runs on a
 * writer thread with its own connection, so the event loop never
 * waits for an fsync or for another process's write lock; a write that
 * cannot get the lock within the busy timeout fails with 503 E_UNAVAILABLE.
 * The listings of drops (sqlite-reader-thread.js), whose cost grows with
 * what they cover, run on a reader thread with a read-only connection;
 * point reads run on this connection (WAL: no read waits for a writer),
 * async only to share one interface with the PostgreSQL store. An
 * in-memory database has no second connection: its writes and listings
 * run here.
 * @implements {import('./ledger-store.js').LedgerStore}
 */
export class SqliteStore {
  /**
   * @param {{ file: string, busyTimeoutMs?: number, checkpointIntervalMs?: number }} options file: path
   *   or ':memory:'; checkpointIntervalMs: how often the checkpoint thread copies the WAL into the file
   */
  constructor ({ file, busyTimeoutMs, checkpointIntervalMs }) {
    this.kind = 'sqlite'
    // Room to start and settle on a full disk (disk-reserve.js).
    this.reserve = file === ':memory:' ? null : new DiskReserve(`${file}.reserve`)
    this.reserve?.releaseIfLow()
    this.db = openSqliteDatabase(file, { busyTimeoutMs })
    if (this.reserve) checkpointLeftoverWal(this.db)
    this._statements = new Map()
    this._writer = file === ':memory:' ? null : new SqliteThreadClient(WRITER_THREAD, { file, busyTimeoutMs, nice: WRITER_THREAD_NICE })
    this._reader = file === ':memory:' ? null : new SqliteThreadClient(READER_THREAD, { file, busyTimeoutMs, nice: READER_THREAD_NICE })
    // The writer's commits never checkpoint; this thread does, beside them (sqlite-checkpoint-thread.js).
    this.checkpointer = file === ':memory:'
      ? null
      : new SqliteCheckpointer(file, { intervalMs: checkpointIntervalMs, nice: WRITER_THREAD_NICE, busyTimeoutMs, finish: () => this._finishCheckpoint() })
    this._writesHere = null
    this._readsHere = null
  }

  /** One write (sqlite-writer-thread.js), on the writer thread, durable when it resolves. */
  async _write (op, args) {
    try {
      if (!this._writer) {
        this._writesHere ??= prepareWrites(this.db)
        return this._writesHere[op](args)
      }
      this.checkpointer.start()
      const result = await this._writer.run(op, args)
      this.reserve?.restore()
      return result
    } catch (error) {
      // The disk is full: give the retries the reserve's space.
      if (error.code === 'SQLITE_FULL') this.reserve?.release()
      if (error.code === 'SQLITE_BUSY') throw gameError('E_UNAVAILABLE', 'the ledger is busy (another process holds its write lock); try again shortly', { cause: error })
      throw error
    }
  }

  /** One listing (sqlite-reader-thread.js), on the reader thread. */
  async _read (op, args) {
    if (!this._reader) {
      this._readsHere ??= prepareReads(this.db)
      return this._readsHere[op](args)
    }
    return this._reader.run(op, args)
  }

  /** The writer copies what the checkpoint thread's pass left (a failure: the next pass tries again). */
  _finishCheckpoint () {
    this._writer.run('checkpoint').catch(() => {})
  }

  /** Cached prepared statement. @param {string} sql */
  _sql (sql) {
    let statement = this._statements.get(sql)
    if (!statement) this._statements.set(sql, (statement = this.db.prepare(sql)))
    return statement
  }

  async migrate () {
    this.db.exec(MIGRATIONS_TABLE)
    const applied = new Set(this.db.prepare('SELECT version FROM schema_migrations').all().map((row) => row.version))
    for (const migration of MIGRATIONS) {
      if (applied.has(migration.version)) continue
      immediateTransaction(this.db, () => {
        this.db.exec(migration.sql)
        this.db.prepare('INSERT INTO schema_migrations (version, name, applied_at) VALUES (?, ?, ?)')
          .run(migration.version, migration.name, Date.now())
      })
    }
  }

  async createPlayer (player) {
    await this._write('createPlayer', player)
  }

  async findPlayerIdByTokenHash (tokenHash) {
    return this._sql('SELECT id FROM players WHERE token_hash = ?').get(tokenHash)?.id ?? null
  }

  async loadAccount (playerId) {
    const row = this._sql(`SELECT p.id, p.balance, p.client_seed, p.created_at,
        s.id AS seed_id, s.seed, s.hash, ${NEXT_NONCE_SQL.sqlite} AS next_nonce
      FROM players p JOIN server_seeds s ON s.player_id = p.id AND s.active = 1
      WHERE p.id = ?`).get(playerId)
    return row ? accountFromRow(row) : null
  }

  /** @param {import('./records.js').LedgerBatch} batch @returns {Promise<import('../game/money.js').CommitOutcome>} */
  async commitBatch (batch) {
    return this._write('commitBatch', batch)
  }

  async rotateSeed (rotation) {
    await this._write('rotateSeed', rotation)
  }

  async getDrop (id) {
    const row = this._sql(`SELECT ${DROP_COLUMNS_WITH_REVEALED_SEED} FROM drops d
      JOIN server_seeds s ON s.id = d.server_seed_id WHERE d.id = ?`).get(id)
    return row ? toDropRecord(row) : null
  }

  /** The server seed behind a drop, revealed or not: for the operator's checks only, never returned to anyone. */
  async getServerSeedOfDrop (id) {
    return this._sql('SELECT s.seed FROM drops d JOIN server_seeds s ON s.id = d.server_seed_id WHERE d.id = ?').get(id)?.seed ?? null
  }

  async listDrops (filter) {
    return listedPage(await this._read('listDrops', filter), filter.beforeId)
  }

  /** Every match, oldest first, EXPORT_PAGE_DROPS at a time from the reader thread. */
  iterateDrops (filter, pageSize = EXPORT_PAGE_DROPS) {
    return dropsInPages(async (afterId) => listedPage(await this._read('dropsPage', { filter, afterId, pageSize }), afterId), pageSize)
  }

  async listInFlightDrops () {
    return this._sql("SELECT * FROM drops WHERE status = 'in_flight' ORDER BY id").all().map(toDropRecord)
  }

  async listSeeds (playerId) {
    return this._sql(`SELECT s.id, s.hash, s.active, ${NEXT_NONCE_SQL.sqlite} AS next_nonce, s.created_at, s.revealed_at,
        CASE WHEN s.revealed_at IS NULL THEN NULL ELSE s.seed END AS revealed_seed
      FROM server_seeds s WHERE s.player_id = ? ORDER BY s.created_at DESC, s.id`).all(playerId).map(seedFromRow)
  }

  async roomStats (room, engineVersion) {
    const buckets = this._sql(ROOM_STATS_SQL.sqlite.buckets).all(room, engineVersion)
    return statsFromRows(buckets, this._sql(ROOM_STATS_SQL.sqlite.inFlight).get(room, engineVersion).n)
  }

  async maxDropId () {
    return Number(this._sql('SELECT COALESCE(MAX(id), 0) AS id FROM drops').get().id)
  }

  async close () {
    // The checkpoint thread first: it asks the writer for work, and the writer's close waits for what it was given.
    await this.checkpointer?.close()
    await this._writer?.close()
    await this._reader?.close()
    await this.reserve?.idle()
    if (this.db.isOpen) this.db.close()
  }
}

/**
 * The writer thread's nice value: below the event loop's 0, so that where
 * both want the same core the ticks go first (a commit waits a little; at
 * the most players one core holds, see loadtest/RESULTS.md). Not so low
 * that it starves: at 19 the commits fell behind and merged into batches
 * large enough to delay the acks (drop → dropped p99 0.55 s). Past what
 * the core holds the acks still fall behind at 10 (6,000 players on a slow
 * VM: p99 1.0–4.4 s); at 5 they kept up (0.40–0.63 s), but 74–104 of the
 * 6,000 players' connections failed during the ramp where none did at 10
 * (loadtest/RESULTS.md, 6 December 2026).
 */
export const WRITER_THREAD_NICE = 10

/**
 * The reader thread's nice value: below the writer's too, so that on a
 * busy core an operator's long listing gives way to the commits the
 * players wait for.
 */
export const READER_THREAD_NICE = 15
