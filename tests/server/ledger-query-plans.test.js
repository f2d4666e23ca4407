import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { openStore } from '../../server/store/open-store.js'
import { SQLITE_SEED_NONCE_INDEX } from '../../server/store/drop-pages.js'

/**
 * The operator's reads of a room, a player and a seed must each read what
 * they return and not the ledger's history: a room's statistics run on
 * the event loop, and a listing's page on the reader thread holds the
 * operator (and each page of an export) for as long as it reads (an
 * in-memory store, as here, runs the same statements on its own
 * connection). Every statement the store prepares for them is planned by
 * SQLite through an index, with no sort of its own (a sort means every
 * matching drop was read first) and no scan of a whole table.
 */
describe('the SQLite ledger\'s plans for the operator\'s reads', () => {
  let store
  /** @type {string[]} the statements the store prepared or took from its cache since plansOf began */
  let prepared = []
  let prepare
  beforeAll(async () => {
    store = await openStore({ kind: 'sqlite', file: ':memory:' })
    // A seed to name by its hash: the store reads it (its id and player) before it plans a page of its drops.
    await store.createPlayer({ id: 'player', tokenHash: 'token', balance: 0, clientSeed: 'c', createdAt: 1, seed: { id: 'seed', seed: 's'.repeat(64), hash: 'hash' } })
    // A drop of that seed, for a page's cursor to name.
    store.db.exec(`INSERT INTO drops (id, player_id, room, rows, risk, engine_version, server_seed_id, server_seed_hash, client_seed, nonce,
      drop_seed, bet, start_tick, status, created_at, payout_rule) VALUES (7, 'player', '16-medium', 16, 'medium', '2.0.0', 'seed', 'hash', 'c', 3,
      '${'d'.repeat(64)}', 1, 0, 'in_flight', 1, 2)`)
    // Statements prepared anew, and those the store keeps prepared (_sql).
    prepare = store.db.prepare.bind(store.db)
    store.db.prepare = (sql) => { prepared.push(sql); return prepare(sql) }
    const cached = store._sql.bind(store)
    store._sql = (sql) => { prepared.push(sql); return cached(sql) }
  })
  afterAll(async () => { await store?.close() })

  /** What `read` prepared, each statement's plan as SQLite's EXPLAIN QUERY PLAN lines. */
  async function plansOf (read) {
    prepared = []
    await read()
    expect(prepared.length).toBeGreaterThan(0)
    const statements = [...new Set(prepared)]
    prepared = []
    return statements.map((sql) => ({ sql, plan: prepare(`EXPLAIN QUERY PLAN ${sql}`).all(...new Array(countParameters(sql)).fill('x')).map((row) => row.detail) }))
  }

  const reads = [
    ['a room\'s statistics', () => store.roomStats('16-medium', '2.0.0')],
    ['a page of a room\'s drops, newest first', () => store.listDrops({ room: '16-medium', limit: 100 })],
    ['the next page of a room\'s drops', () => store.listDrops({ room: '16-medium', beforeId: 1000, limit: 100 })],
    ['a page of a player\'s drops', () => store.listDrops({ playerId: 'player', limit: 100 })],
    ['the next page of a player\'s drops', () => store.listDrops({ playerId: 'player', beforeId: 7, limit: 100 })],
    ['a page of a player\'s drops in a room and a time window', () => store.listDrops({ playerId: 'player', room: '16-medium', from: 0, to: 10, limit: 100 })],
    ['a page of a seed\'s drops, newest first', () => store.listDrops({ serverSeedHash: 'hash', limit: 100 })],
    ['a seed\'s drop by its nonce', () => store.listDrops({ serverSeedHash: 'hash', nonce: 3, limit: 10 })],
    ['an export\'s page of a seed\'s drops', () => firstPage(store.iterateDrops({ serverSeedHash: 'hash' }))],
    ['an export\'s page of a player\'s drops', () => firstPage(store.iterateDrops({ playerId: 'player' }))],
    ['an export\'s next page of a player\'s drops', () => store.iterateDrops({ playerId: 'player' }, 1).next().then(() => undefined)]
  ]
  it.each(reads)('%s: through an index, no sort, no scan of a table', async (name, read) => {
    for (const { sql, plan } of await plansOf(read)) {
      const lines = plan.join(' | ')
      expect(lines, sql).not.toMatch(/TEMP B-TREE/)
      // A SCAN is allowed only along an index (the drops in flight: a few rows whatever the history).
      for (const line of plan) if (/^SCAN /.test(line)) expect(line, sql).toMatch(/USING (COVERING )?INDEX drops_in_flight/)
    }
  })

  it('reads a room\'s drops through drops_room_id, its statistics from room_buckets, its drops in flight through drops_in_flight', async () => {
    const [listing] = await plansOf(() => store.listDrops({ room: '16-medium', limit: 100 }))
    expect(listing.plan.join(' | ')).toMatch(/drops_room_id \(room=\?/)
    const stats = await plansOf(() => store.roomStats('16-medium', '2.0.0'))
    expect(stats.map((s) => s.plan.join(' | ')).join(' || ')).toMatch(/room_buckets USING INDEX/)
    // Its drops in flight through the partial index: drops_room_id would walk every drop of the room.
    expect(stats.find((s) => /in_flight/.test(s.sql)).plan.join(' | ')).toMatch(/USING (COVERING )?INDEX drops_in_flight/)
  })

  it('reads a player\'s drops seed by seed, through their seeds in creation order (server_seeds_order) and each seed\'s nonces (UNIQUE (server_seed_id, nonce)), from the cursor on', async () => {
    // SQLITE_SEED_NONCE_INDEX names that unique index.
    expect(store.db.prepare(`PRAGMA index_info('${SQLITE_SEED_NONCE_INDEX.replace('INDEXED BY ', '')}')`).all().map((c) => c.name)).toEqual(['server_seed_id', 'nonce'])
    const plans = await plansOf(() => store.listDrops({ playerId: 'player', beforeId: 7, limit: 100 }))
    const all = plans.map((p) => p.plan.join(' | ')).join(' || ')
    expect(all).toMatch(/INDEX sqlite_autoindex_drops_2 \(server_seed_id=\? AND nonce<\?\)/)
    expect(all).toMatch(/server_seeds USING (COVERING )?INDEX server_seeds_order \(player_id=\? AND \(created_at,id\)<\(\?,\?\)\)/)
    expect(all).not.toMatch(/drops_player/)
    const page = await plansOf(() => firstPage(store.iterateDrops({ serverSeedHash: 'hash' })))
    expect(page.map((p) => p.plan.join(' | ')).join(' || ')).toMatch(/INDEX sqlite_autoindex_drops_2 \(server_seed_id=\?\)/)
    const byNonce = await plansOf(() => store.listDrops({ serverSeedHash: 'hash', nonce: 3, limit: 10 }))
    expect(byNonce.map((p) => p.plan.join(' | ')).join(' || ')).toMatch(/INDEX sqlite_autoindex_drops_2 \(server_seed_id=\? AND nonce=\?\)/)
  })
})

/** Reads an iteration's first page (the store reads a page at a time). */
async function firstPage (drops) {
  for await (const drop of drops) return drop
}

function countParameters (sql) {
  return (sql.match(/\?/g) ?? []).length
}
