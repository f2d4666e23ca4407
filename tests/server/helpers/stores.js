import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { DatabaseSync } from 'node:sqlite'
import pg from 'pg'
import { startPostgres } from '../../../tools/postgres-process.js'

/** The store kinds every ledger test runs against (describe.each). */
export const STORE_KINDS = ['sqlite', 'postgres']

/**
 * One backend per test file: setup() in beforeAll, teardown() in afterAll.
 * newDatabase() gives an empty database (a temp SQLite file, or a fresh
 * PostgreSQL database) as a config `database` entry plus its DATABASE_URL;
 * query() reads it directly, bypassing the server, for cross-checks.
 * @param {'sqlite' | 'postgres'} kind
 */
export function storeBackend (kind) {
  return kind === 'postgres' ? postgresBackend() : sqliteBackend()
}

function sqliteBackend () {
  let dir
  let count = 0
  return {
    kind: 'sqlite',
    async setup () { dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-sqlite-')) },
    async teardown () { fs.rmSync(dir, { recursive: true, force: true }) },
    async newDatabase () {
      const file = path.join(dir, `ledger-${count++}.sqlite`)
      return { url: `sqlite:${file}`, database: { kind: 'sqlite', file } }
    },
    async query (database, sql, params = []) {
      const db = new DatabaseSync(database.file)
      try {
        const statement = db.prepare(sql.replace(/\$\d+/g, '?'))
        return statement.columns().length > 0 ? statement.all(...params) : (statement.run(...params), [])
      } finally {
        db.close()
      }
    }
  }
}

/** BIGINT and NUMERIC as numbers, like SQLite returns them. */
const numericTypes = {
  getTypeParser: (oid, format) => (oid === 20 || oid === 1700 ? Number : pg.types.getTypeParser(oid, format))
}

function postgresBackend () {
  let server
  return {
    kind: 'postgres',
    async setup () { server = await startPostgres() },
    async teardown () { await server?.stop() },
    async newDatabase () {
      const url = await server.createDatabase()
      return { url, database: { kind: 'postgres', url } }
    },
    async query (database, sql, params = []) {
      const client = new pg.Client({ connectionString: database.url, types: numericTypes })
      await client.connect()
      try {
        return (await client.query(sql, params)).rows
      } finally {
        await client.end()
      }
    }
  }
}

/**
 * A room's settled drops summed by bucket straight from the drops table,
 * in the shape of the store's roomStats (payout in credits), and its drops
 * in flight: what the totals the ledger keeps must equal.
 * @param {ReturnType<typeof storeBackend>} backend @param {object} database
 * @param {string} room @param {string} engineVersion
 */
export async function roomSumsOverDrops (backend, database, room, engineVersion) {
  const buckets = await backend.query(database, `SELECT bucket, COUNT(*) AS count, SUM(bet) AS bet, SUM(payout) AS payout FROM drops
    WHERE room = $1 AND engine_version = $2 AND status = 'settled' GROUP BY bucket ORDER BY bucket`, [room, engineVersion])
  const [{ n }] = await backend.query(database, "SELECT COUNT(*) AS n FROM drops WHERE room = $1 AND engine_version = $2 AND status = 'in_flight'", [room, engineVersion])
  return {
    buckets: buckets.map((row) => ({ bucket: Number(row.bucket), count: Number(row.count), bet: Number(row.bet), payout: Number(row.payout) / 1000 })),
    inFlight: Number(n)
  }
}
