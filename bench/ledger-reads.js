#!/usr/bin/env node
/**
 * What the operator's long reads of a ledger cost, and how long the event
 * loop (which ticks the rooms) is held while they run.
 * `node bench/ledger-reads.js [--drops 1000000] [--ledger sqlite|postgres]` (run by hand;
 * postgres: a throwaway server, tools/postgres-process.js, analyzed after the fill).
 *
 * Builds a ledger of `--drops` settled drops (1,000 players with two seeds
 * each, the first retired; a quarter of the drops are one heavy player's,
 * half of those on each of its seeds; 100 rooms; one drop a millisecond),
 * opens it with the real store (server/store/open-store.js) and, for each
 * read, prints its duration and the longest pause of the event loop while
 * it ran (the longest gap between two setImmediate turns). The first line
 * reads nothing (a 300 ms timer): the pauses the machine gives anyway.
 * Exit code 0 whatever the figures.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { DatabaseSync } from 'node:sqlite'
import pg from 'pg'
import { openStore } from '../server/store/open-store.js'
import { startPostgres } from '../tools/postgres-process.js'

const { values } = parseArgs({ options: { drops: { type: 'string', default: '1000000' }, ledger: { type: 'string', default: 'sqlite' } } })
const DROPS = Number(values.drops)
if (!Number.isInteger(DROPS) || DROPS < 10_000 || !['sqlite', 'postgres'].includes(values.ledger)) {
  console.error('usage: node bench/ledger-reads.js [--drops N] [--ledger sqlite|postgres] (N an integer, at least 10000)')
  process.exit(2)
}

/** Which player drop i is: a quarter of them player 7's, the rest spread over the 1,000. */
const HEAVY = 'CASE WHEN i % 4 = 0 THEN 7 ELSE i % 1000 END'

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-ledger-reads-'))
const postgres = values.ledger === 'postgres' ? await startPostgres() : null
try {
  // The store creates the schema; the drops go in through a connection of their own.
  const database = postgres ? { kind: 'postgres', url: await postgres.createDatabase() } : { kind: 'sqlite', file: path.join(dir, 'ledger.sqlite') }
  await (await openStore(database)).close()
  if (postgres) await fillPostgres(database.url)
  else fillSqlite(database.file)
  const store = await openStore(database)
  const heavySeed = 'hash-7'
  const count = async (drops) => { let n = 0; for await (const _ of drops) n++; return n }
  console.log(`${postgres ? 'PostgreSQL' : 'SQLite'} ledger of ${DROPS.toLocaleString('en-US')} settled drops: each read's time, and the event loop's longest pause while it ran`)
  await store.listDrops({ room: '16-medium.1', limit: 1 })
  await probe('nothing (a 300 ms timer)', async () => { await new Promise((resolve) => setTimeout(resolve, 300)); return 0 })
  await probe(`a page of a ${Math.round(DROPS / 10).toLocaleString('en-US')}-drop time window`, async () => (await store.listDrops({ from: Math.round(DROPS * 0.2), to: Math.round(DROPS * 0.3), limit: 100 })).length)
  await probe('a page of the drops up to a time', async () => (await store.listDrops({ to: Math.round(DROPS * 0.2), limit: 100 })).length)
  await probe('a page of a busy room\'s drops', async () => (await store.listDrops({ room: '16-medium.7', limit: 100 })).length)
  await probe('a page of the heavy player\'s drops', async () => (await store.listDrops({ playerId: 'player-7', limit: 100 })).length)
  // Drop 0.4 × DROPS (a multiple of 4) is the heavy player's, on their first seed: a page from the middle of their history.
  await probe('a page of theirs from the middle of their history', async () => (await store.listDrops({ playerId: 'player-7', beforeId: Math.round(DROPS * 0.1) * 4, limit: 100 })).length)
  await probe('a page of theirs in a room', async () => (await store.listDrops({ playerId: 'player-7', room: '16-medium.8', limit: 100 })).length)
  await probe('the heavy player\'s retired seed, exported whole', () => count(store.iterateDrops({ serverSeedHash: heavySeed })))
  await probe('the heavy player, exported whole', () => count(store.iterateDrops({ playerId: 'player-7' })))
  await store.close()
} finally {
  await postgres?.stop()
  fs.rmSync(dir, { recursive: true, force: true })
}

function fillSqlite (target) {
  const db = new DatabaseSync(target)
  try {
    db.exec(`BEGIN;
      WITH RECURSIVE n(i) AS (SELECT 0 UNION ALL SELECT i + 1 FROM n WHERE i < 999)
      INSERT INTO players (id, token_hash, balance, client_seed, created_at) SELECT 'player-' || i, 'token-' || i, 0, 'c', 0 FROM n;
      WITH RECURSIVE n(i) AS (SELECT 0 UNION ALL SELECT i + 1 FROM n WHERE i < 1999)
      INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at, revealed_at)
      SELECT 'seed-' || i, 'player-' || (i % 1000), 'seed', 'hash-' || i, i >= 1000, 0, i, CASE WHEN i >= 1000 THEN NULL ELSE 1 END FROM n;
      WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < ${DROPS})
      INSERT INTO drops (id, player_id, room, rows, risk, engine_version, server_seed_id, server_seed_hash, client_seed, nonce, drop_seed,
        bet, bucket, multiplier, payout, start_tick, ticks, state_hash, status, created_at, settled_at, payout_rule)
      SELECT i, 'player-' || (${HEAVY}), '16-medium.' || (i % 100), 16, 'medium', '2.0.0',
        'seed-' || ((${HEAVY}) + CASE WHEN i > ${DROPS / 2} THEN 1000 ELSE 0 END), 'hash', 'c', i, printf('%064d', i), 10, i % 17, 1.0, 10000, i, 180,
        'abcd', 'settled', i, i + 1, 2 FROM n;
      COMMIT`)
  } finally {
    db.close()
  }
}

async function fillPostgres (url) {
  const client = new pg.Client({ connectionString: url })
  await client.connect()
  try {
    await client.query(`INSERT INTO players (id, token_hash, balance, client_seed, created_at) SELECT 'player-' || i, 'token-' || i, 0, 'c', 0 FROM generate_series(0, 999) i`)
    await client.query(`INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at, revealed_at)
      SELECT 'seed-' || i, 'player-' || (i % 1000), 'seed', 'hash-' || i, CASE WHEN i >= 1000 THEN 1 ELSE 0 END, 0, i, CASE WHEN i >= 1000 THEN NULL ELSE 1 END
      FROM generate_series(0, 1999) i`)
    await client.query(`INSERT INTO drops (id, player_id, room, rows, risk, engine_version, server_seed_id, server_seed_hash, client_seed, nonce, drop_seed,
        bet, bucket, multiplier, payout, start_tick, ticks, state_hash, status, created_at, settled_at, payout_rule)
      SELECT i, 'player-' || (${HEAVY}), '16-medium.' || (i % 100), 16, 'medium', '2.0.0',
        'seed-' || ((${HEAVY}) + CASE WHEN i > ${DROPS / 2} THEN 1000 ELSE 0 END), 'hash', 'c', i, lpad(i::text, 64, '0'), 10, i % 17, 1.0, 10000, i, 180,
        'abcd', 'settled', i, i + 1, 2 FROM generate_series(1, ${DROPS}) i`)
    await client.query('ANALYZE')
  } finally {
    await client.end()
  }
}

/** Runs `read`, printing its rows, duration and the event loop's longest pause meanwhile. */
async function probe (label, read) {
  let last = performance.now()
  let longest = 0
  let running = true
  const turn = () => {
    const now = performance.now()
    longest = Math.max(longest, now - last)
    last = now
    if (running) setImmediate(turn)
  }
  setImmediate(turn)
  const started = performance.now()
  const rows = await read()
  const took = performance.now() - started
  running = false
  await new Promise((resolve) => setImmediate(resolve))
  console.log(`${label.padEnd(52)} ${String(rows).padStart(7)} drops  ${took.toFixed(0).padStart(6)} ms  event loop's longest pause ${longest.toFixed(1)} ms`)
}
