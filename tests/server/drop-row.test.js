import { describe, it, expect } from 'vitest'
import { DatabaseSync } from 'node:sqlite'
import { MIGRATIONS, MIGRATIONS_TABLE } from '../../server/store/migrations.js'
import { NEW_DROP_COLUMNS, SETTLEMENT_COLUMNS, DROP_SQL, newDropValues, settlementValues, newDropArrays, settlementArrays, toDropRecord } from '../../server/store/records.js'
import { newDropRow, settlementRow } from '../../server/game/drop.js'

/**
 * The drop row is named in one place (server/store/records.js): its column
 * lists are the drops table's columns, the game's rows carry exactly their
 * fields, and a row written by the statements built from them reads back as
 * the record it was written from.
 */
const drop = {
  id: 7, playerId: 'p1', roomId: '16-medium', rows: 16, risk: 'medium', engineVersion: '2.0.0', seedId: 's1',
  serverSeedHash: 'b'.repeat(64), clientSeed: 'client', nonce: 3, dropSeed: 'd'.repeat(64), bet: 10, payoutRule: 2,
  createdAt: Date.UTC(2026, 11, 1, 12), startTick: 120
}
const landing = { drop, bucket: 4, multiplier: 1.5, payout: 15_000, ticks: 200, stateHash: '0123456789abcdef', settledAt: Date.UTC(2026, 11, 1, 12, 0, 4) }

function ledger () {
  const db = new DatabaseSync(':memory:')
  db.exec(MIGRATIONS_TABLE)
  for (const migration of MIGRATIONS) db.exec(migration.sql)
  db.prepare('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES (?, ?, ?, ?, ?)').run('p1', 'h', 0, 'client', 1)
  db.prepare('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES (?, ?, ?, ?, 1, 0, 1)').run('s1', 'p1', 'a'.repeat(64), 'b'.repeat(64))
  return db
}

describe('the drop row', () => {
  it('names every column of the drops table once: a new drop\'s, a settlement\'s, and the status', () => {
    const table = ledger().prepare('PRAGMA table_info(drops)').all().map((c) => c.name)
    const named = [...NEW_DROP_COLUMNS, ...SETTLEMENT_COLUMNS].map((c) => c.name)
    expect(new Set(named).size).toBe(named.length)
    expect([...named, 'status'].sort()).toEqual([...table].sort())
  })

  it('is what the game hands the ledger: its rows have exactly the columns\' fields', () => {
    expect(Object.keys(newDropRow(drop)).sort()).toEqual(NEW_DROP_COLUMNS.map((c) => c.field).sort())
    expect(Object.keys(settlementRow(landing)).sort()).toEqual(['id', ...SETTLEMENT_COLUMNS.map((c) => c.field)].sort())
  })

  it('reads back, written by the SQLite statements, as the record it was written from', () => {
    const db = ledger()
    const row = newDropRow(drop)
    db.prepare(DROP_SQL.sqlite.insert).run(...newDropValues(row))
    const written = toDropRecord(db.prepare('SELECT * FROM drops WHERE id = 7').get())
    expect(written).toEqual({
      id: 7, playerId: 'p1', room: '16-medium', rows: 16, risk: 'medium', engineVersion: '2.0.0', serverSeedHash: 'b'.repeat(64),
      clientSeed: 'client', nonce: 3, dropSeed: 'd'.repeat(64), bet: 10, bucket: null, multiplier: null, payout: null, payoutRule: 2,
      startTick: 120, ticks: null, stateHash: null, status: 'in_flight', createdAt: '2026-12-01T12:00:00.000Z', settledAt: null
    })
    const settle = db.prepare(DROP_SQL.sqlite.settle)
    expect(settle.run(...settlementValues(settlementRow(landing))).changes).toBe(1)
    // Only a drop still in flight is settled.
    expect(settle.run(...settlementValues(settlementRow(landing))).changes).toBe(0)
    expect(toDropRecord(db.prepare('SELECT * FROM drops WHERE id = 7').get())).toEqual({
      ...written, bucket: 4, multiplier: 1.5, payout: 15, ticks: 200, stateHash: '0123456789abcdef', status: 'settled', settledAt: '2026-12-01T12:00:04.000Z'
    })
  })

  it('travels to PostgreSQL as one array per column, in the order of its unnest()', () => {
    const rows = [newDropRow(drop), newDropRow({ ...drop, id: 8, nonce: 4 })]
    const arrays = newDropArrays(rows)
    expect(arrays).toHaveLength(NEW_DROP_COLUMNS.length)
    expect(arrays[NEW_DROP_COLUMNS.findIndex((c) => c.name === 'nonce')]).toEqual([3, 4])
    expect(DROP_SQL.postgres.insert).toContain(`$${NEW_DROP_COLUMNS.length}::bigint[]`)
    const settlements = settlementArrays([settlementRow(landing)])
    expect(settlements).toEqual([[7], [4], [1.5], [15_000], [200], ['0123456789abcdef'], [landing.settledAt]])
    expect(DROP_SQL.postgres.settle).toMatch(/unnest\(\$1::bigint\[\], \$2::smallint\[\].*AS s \(id, bucket/)
  })
})
