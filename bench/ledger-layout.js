#!/usr/bin/env node
/**
 * Would a leaner ledger layout make the SQLite writer cheaper per drop?
 * `node bench/ledger-layout.js [--players 4500] [--per-batch 37] [--batches 800] [--rounds 3]`
 * (run by hand; issue #23's "a different ledger layout").
 *
 * The writer thread's transactions (server/store/sqlite-writer-thread.js
 * prepareWrites().commitBatch, the real statements) on a fresh database
 * (server/store/sqlite-database.js: WAL, synchronous=FULL, its automatic
 * checkpoint off, as the writer's is) with the reference load of a busy
 * process: `--players` players, batches of `--per-batch` new drops (one a
 * tick: 4,500 players dropping every 2 s is 37.5 a tick), each drop
 * debiting its player, and the drops of 180 batches before (a flight)
 * settled and credited. A batch here is one tick's; the server's
 * transactions gather LEDGER_COMMIT_TICKS ticks (default 2), so
 * `--per-batch 75` is nearer a process of 4,500 players (its 180 batches
 * then stand for two flights: each drop settles later, on the same kind
 * of pages). Layouts:
 *
 * - as shipped (server/store/migrations.js): each settlement adds its drop
 *   to its room's totals (room_buckets, migration 3), drops_room_id
 *   (room, id) replaces drops_room, and no index of drops by player
 *   (migration 4: a player's history goes through their seeds);
 * - before migration 4: the drops_player index (player_id, id) as well;
 * - before migration 3: the drops_room index, and no room totals (the
 *   writer's statement adding to them still runs, its insert ignored by a
 *   trigger: a lookup of the drop's row by id);
 * - the shipped schema in a file of 1,024- or 2,048-byte pages instead of
 *   SQLite's 4,096 (each random write then logs a smaller page; the B-trees
 *   are deeper).
 *
 * Each index is a write at a random place per drop (a player's or a
 * room's page). Another such write, each batch's update of its seeds'
 * next_nonce, is gone since 5 December 2026 (a seed's next nonce is now
 * read from its drops: server/store/records.js NEXT_NONCE_SQL); this bench
 * measured it at 0.67–0.81× of the writer before. Printed per layout, median (range) over the
 * rounds, layouts interleaved round by round: the thread's CPU µs per drop
 * (user and system: process.cpuUsage, nothing else runs) and WAL pages
 * written per drop (what the commit writes and the checkpoint then copies).
 * Exit code 0 whatever the figures.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import crypto from 'node:crypto'
import { parseArgs } from 'node:util'
import { DatabaseSync } from 'node:sqlite'
import { MIGRATIONS } from '../server/store/migrations.js'
import { openSqliteDatabase } from '../server/store/sqlite-database.js'
import { prepareWrites } from '../server/store/sqlite-writer-thread.js'

const { values } = parseArgs({ options: { players: { type: 'string', default: '4500' }, 'per-batch': { type: 'string', default: '37' }, batches: { type: 'string', default: '800' }, rounds: { type: 'string', default: '3' } } })
const PLAYERS = Number(values.players)
const PER_BATCH = Number(values['per-batch'])
const BATCHES = Number(values.batches)
const ROUNDS = Number(values.rounds)
if (![PLAYERS, PER_BATCH, BATCHES, ROUNDS].every((n) => Number.isInteger(n) && n > 0)) {
  console.error('usage: node bench/ledger-layout.js [--players N] [--per-batch N] [--batches N] [--rounds N] (positive integers)')
  process.exit(2)
}
const FLIGHT_BATCHES = 180
const WARM_UP_BATCHES = FLIGHT_BATCHES + 200
const ROOMS = 100

// Before migration 3, room_buckets did not exist: here it takes no row, so the writer's statement for it changes nothing.
const ROOM_TOTALS_IGNORED = `CREATE TABLE room_buckets (room TEXT, engine_version TEXT, bucket SMALLINT, settled BIGINT, bet BIGINT, payout BIGINT,
  PRIMARY KEY (room, engine_version, bucket));
CREATE TRIGGER room_buckets_ignored BEFORE INSERT ON room_buckets BEGIN SELECT RAISE(IGNORE); END;`

const LAYOUTS = [
  { name: 'as shipped', migrations: MIGRATIONS },
  { name: 'before migration 4', migrations: MIGRATIONS.filter((m) => m.version < 4) },
  { name: 'before migration 3', migrations: MIGRATIONS.filter((m) => m.version < 3), then: ROOM_TOTALS_IGNORED },
  { name: 'pages of 1,024 bytes', migrations: MIGRATIONS, pageSize: 1024 },
  { name: 'pages of 2,048 bytes', migrations: MIGRATIONS, pageSize: 2048 }
]

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-ledger-layout-'))
const results = new Map(LAYOUTS.map((layout) => [layout.name, []]))
try {
  for (let round = 0; round < ROUNDS; round++) {
    for (const layout of round % 2 === 0 ? LAYOUTS : [...LAYOUTS].reverse()) results.get(layout.name).push(run(layout, path.join(dir, `r${round}.sqlite`)))
  }
} finally {
  fs.rmSync(dir, { recursive: true, force: true })
}

console.log(`SQLite writer per drop: ${PLAYERS} players, ${PER_BATCH} new drops and as many settlements a transaction, ${BATCHES} transactions measured after ${WARM_UP_BATCHES}; median (range) of ${ROUNDS} rounds`)
console.log('layout                      CPU µs per drop            of it user            of it system          WAL pages per drop')
const shipped = median(results.get('as shipped').map((r) => r.cpu))
for (const layout of LAYOUTS) {
  const runs = results.get(layout.name)
  const cell = (key, digits = 1) => `${median(runs.map((r) => r[key])).toFixed(digits)} (${Math.min(...runs.map((r) => r[key])).toFixed(digits)}–${Math.max(...runs.map((r) => r[key])).toFixed(digits)})`
  const share = layout.name === 'as shipped' ? '' : `  ${(median(runs.map((r) => r.cpu)) / shipped).toFixed(2)}×`
  console.log(`${layout.name.padEnd(26)}  ${(cell('cpu') + share).padEnd(25)}  ${cell('user').padEnd(20)}  ${cell('system').padEnd(20)}  ${cell('pages', 2)}`)
}

/** One layout on a fresh file: CPU µs and WAL pages per drop over the measured batches. */
function run (layout, file) {
  for (const f of [file, `${file}-wal`, `${file}-shm`]) fs.rmSync(f, { force: true })
  if (layout.pageSize) setPageSize(file, layout.pageSize)
  const db = openSqliteDatabase(file, { autoCheckpoint: false })
  for (const migration of layout.migrations) db.exec(migration.sql)
  if (layout.then) db.exec(layout.then)
  const players = createPlayers(db)
  const writes = prepareWrites(db)
  let nextId = 1
  const inFlight = []
  const batch = () => {
    const drops = []
    const balances = []
    for (let k = 0; k < PER_BATCH; k++) {
      const p = players[crypto.randomInt(players.length)]
      const id = nextId++
      drops.push({ id, playerId: p.id, room: `16-medium-${id % ROOMS}`, rows: 16, risk: 'medium', engineVersion: '1.2.0', serverSeedId: p.seedId, serverSeedHash: p.hash, clientSeed: p.clientSeed, nonce: p.nonce++, dropSeed: crypto.randomBytes(32).toString('hex'), bet: 10, payoutRule: 2, startTick: id * 2, createdAt: Date.now() })
      balances.push({ playerId: p.id, delta: -10_000 })
    }
    const settlements = []
    if (inFlight.length >= FLIGHT_BATCHES) {
      for (const d of inFlight.shift()) {
        settlements.push({ id: d.id, bucket: 7, multiplier: 1.1, payout: 11_000, ticks: 190, stateHash: '0123456789abcdef', settledAt: Date.now() })
        balances.push({ playerId: d.playerId, delta: 11_000 })
      }
    }
    inFlight.push(drops)
    writes.commitBatch({ drops, settlements, balances, clientSeeds: [] })
  }
  for (let i = 0; i < WARM_UP_BATCHES; i++) batch()
  const pageSize = Number(db.prepare('PRAGMA page_size').get().page_size)
  const pagesBefore = walPages(file, pageSize)
  const before = process.cpuUsage()
  for (let i = 0; i < BATCHES; i++) batch()
  const used = process.cpuUsage(before)
  const pages = walPages(file, pageSize) - pagesBefore
  db.close()
  const n = BATCHES * PER_BATCH
  return { cpu: (used.user + used.system) / n, user: used.user / n, system: used.system / n, pages: pages / n }
}

/** A new, empty database file with pages of `bytes`, set before the store's connection turns on WAL (a WAL file keeps its page size). */
function setPageSize (file, bytes) {
  const db = new DatabaseSync(file)
  db.exec(`PRAGMA page_size = ${bytes}`)
  db.exec('VACUUM')
  db.close()
}

function createPlayers (db) {
  const players = []
  const insertPlayer = db.prepare('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES (?, ?, ?, ?, ?)')
  const insertSeed = db.prepare('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES (?, ?, ?, ?, 1, 0, ?)')
  db.exec('BEGIN')
  for (let i = 0; i < PLAYERS; i++) {
    const p = { id: crypto.randomUUID(), seedId: crypto.randomUUID(), hash: crypto.randomBytes(32).toString('hex'), clientSeed: crypto.randomBytes(8).toString('hex'), nonce: 0 }
    insertPlayer.run(p.id, crypto.randomBytes(32).toString('hex'), 1e12, p.clientSeed, Date.now())
    insertSeed.run(p.seedId, p.id, crypto.randomBytes(32).toString('hex'), p.hash, Date.now())
    players.push(p)
  }
  db.exec('COMMIT')
  return players
}

/** Frames in the WAL file (a 32-byte header, then a 24-byte header and a page each): with no checkpoint it only grows. */
function walPages (file, pageSize) {
  return (fs.statSync(`${file}-wal`).size - 32) / (pageSize + 24)
}

function median (values) {
  const sorted = [...values].sort((a, b) => a - b)
  const middle = sorted.length >> 1
  return sorted.length % 2 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2
}
