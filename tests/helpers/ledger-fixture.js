import fs from 'node:fs'
import { fileURLToPath } from 'node:url'
import { DatabaseSync } from 'node:sqlite'
import pg from 'pg'
import { MIGRATIONS, MIGRATIONS_TABLE } from '../../server/store/migrations.js'

/**
 * A ledger recorded by a real server of an older engine version
 * (tests/fixtures/ledger-VERSION/, made by tests/fixtures/record-ledger-fixture.js):
 * the database as that server left it, and what its players saw.
 * @param {string} version
 */
export function ledgerFixture (version) {
  const dir = fileURLToPath(new URL(`../fixtures/ledger-${version}/`, import.meta.url))
  return { dir, sqliteFile: `${dir}ledger.sqlite`, ...JSON.parse(fs.readFileSync(`${dir}fixture.json`, 'utf8')) }
}

const TABLES = ['schema_migrations', 'players', 'server_seeds', 'drops']

/**
 * Puts a fixture's ledger into a fresh test database (storeBackend().newDatabase()):
 * the SQLite file is copied as it is; for PostgreSQL the schema is built
 * by the migrations the fixture's ledger had (no later ones) and every row
 * copied over, so both stores start from the same old ledger and the
 * server that opens it runs the later migrations on either.
 * @param {{ database: { kind: string, file?: string, url?: string } }} database
 * @param {ReturnType<typeof ledgerFixture>} fixture
 */
export async function loadLedgerFixture (database, fixture) {
  if (database.database.kind === 'sqlite') {
    fs.copyFileSync(fixture.sqliteFile, database.database.file)
    return
  }
  const source = new DatabaseSync(fixture.sqliteFile, { readOnly: true })
  const client = new pg.Client({ connectionString: database.database.url })
  await client.connect()
  try {
    const applied = new Set(source.prepare('SELECT version FROM schema_migrations').all().map((row) => row.version))
    await client.query(MIGRATIONS_TABLE)
    for (const migration of MIGRATIONS) if (applied.has(migration.version)) await client.query(migration.sql)
    for (const table of TABLES) {
      for (const row of source.prepare(`SELECT * FROM ${table} ORDER BY rowid`).all()) {
        const names = Object.keys(row)
        await client.query(`INSERT INTO ${table} (${names.join(', ')}) VALUES (${names.map((_, i) => `$${i + 1}`).join(', ')})`, names.map((n) => row[n]))
      }
    }
  } finally {
    await client.end()
    source.close()
  }
}

/** Every drop row of the fixture's ledger, by id, as recorded (before any upgrade touched it). */
export function fixtureDrops (fixture) {
  return fixtureRows(fixture, 'SELECT * FROM drops ORDER BY id')
}

/** Every player row of the fixture's ledger, as recorded (balances in whole credits). */
export function fixturePlayers (fixture) {
  return fixtureRows(fixture, 'SELECT * FROM players ORDER BY id')
}

function fixtureRows (fixture, sql) {
  const source = new DatabaseSync(fixture.sqliteFile, { readOnly: true })
  try {
    return source.prepare(sql).all()
  } finally {
    source.close()
  }
}
