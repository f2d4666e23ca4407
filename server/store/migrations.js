/**
 * The ledger schema, shared word for word by SQLite and PostgreSQL: only
 * types and constructs both accept (TEXT, BIGINT, SMALLINT, INTEGER,
 * DOUBLE PRECISION, CHECK, partial unique indexes). Money is integer
 * milli-credits in BIGINT (balances and payouts; a bet is whole credits),
 * since migration 2; times are milliseconds since the Unix epoch in BIGINT.
 * Migrations are append-only: never edit one that has shipped.
 */
export const MIGRATIONS = Object.freeze([
  {
    version: 1,
    name: 'players, server seeds and drops',
    sql: `
CREATE TABLE players (
  id          TEXT PRIMARY KEY,
  token_hash  TEXT NOT NULL UNIQUE,
  balance     BIGINT NOT NULL CHECK (balance >= 0),
  client_seed TEXT NOT NULL,
  created_at  BIGINT NOT NULL
);

CREATE TABLE server_seeds (
  id          TEXT PRIMARY KEY,
  player_id   TEXT NOT NULL REFERENCES players (id),
  seed        TEXT NOT NULL,
  hash        TEXT NOT NULL UNIQUE,
  active      SMALLINT NOT NULL CHECK (active IN (0, 1)),
  next_nonce  BIGINT NOT NULL DEFAULT 0 CHECK (next_nonce >= 0),
  created_at  BIGINT NOT NULL,
  revealed_at BIGINT,
  CHECK ((active = 1 AND revealed_at IS NULL) OR (active = 0 AND revealed_at IS NOT NULL))
);
-- One active (committed, unrevealed) seed per player.
CREATE UNIQUE INDEX server_seeds_active ON server_seeds (player_id) WHERE active = 1;
CREATE INDEX server_seeds_player ON server_seeds (player_id, created_at);

CREATE TABLE drops (
  id               BIGINT PRIMARY KEY,
  player_id        TEXT NOT NULL REFERENCES players (id),
  room             TEXT NOT NULL,
  rows             SMALLINT NOT NULL,
  risk             TEXT NOT NULL,
  engine_version   TEXT NOT NULL,
  server_seed_id   TEXT NOT NULL REFERENCES server_seeds (id),
  server_seed_hash TEXT NOT NULL,
  client_seed      TEXT NOT NULL,
  nonce            BIGINT NOT NULL CHECK (nonce >= 0),
  drop_seed        TEXT NOT NULL,
  bet              BIGINT NOT NULL CHECK (bet > 0),
  bucket           SMALLINT,
  multiplier       DOUBLE PRECISION,
  payout           BIGINT CHECK (payout >= 0),
  start_tick       BIGINT NOT NULL,
  ticks            INTEGER,
  state_hash       TEXT,
  status           TEXT NOT NULL CHECK (status IN ('in_flight', 'settled')),
  created_at       BIGINT NOT NULL,
  settled_at       BIGINT,
  -- A nonce is never used twice with the same server seed.
  UNIQUE (server_seed_id, nonce),
  CHECK ((status = 'in_flight' AND settled_at IS NULL AND payout IS NULL)
      OR (status = 'settled' AND settled_at IS NOT NULL AND payout IS NOT NULL AND bucket IS NOT NULL
          AND multiplier IS NOT NULL AND ticks IS NOT NULL AND state_hash IS NOT NULL))
);
-- Few, narrow indexes: every one is paid for on each of the thousands of
-- inserts per second. Drops of a seed are found through server_seeds.hash
-- (unique) and UNIQUE (server_seed_id, nonce); status is left out of
-- drops_room so settling a drop does not move it in that index.
CREATE INDEX drops_player ON drops (player_id, id);
CREATE INDEX drops_created ON drops (created_at);
CREATE INDEX drops_room ON drops (room);
CREATE INDEX drops_in_flight ON drops (id) WHERE status = 'in_flight';
`
  },
  {
    version: 2,
    name: 'money in milli-credits; each drop records its payout rule',
    // Rule 1 (every drop before this migration): floor(bet × multiplier) credits.
    // Rule 2 (every drop after it): bet × multiplier exactly, in milli-credits.
    // See protocol/payout.js; audits recompute each drop under its own rule.
    sql: `
UPDATE players SET balance = balance * 1000;
UPDATE drops SET payout = payout * 1000 WHERE payout IS NOT NULL;
ALTER TABLE drops ADD COLUMN payout_rule SMALLINT NOT NULL DEFAULT 1 CHECK (payout_rule IN (1, 2));
`
  },
  {
    version: 3,
    name: 'room totals by bucket kept with each settlement; drops by room in id order',
    // The room statistics were a GROUP BY over every settled drop of the room,
    // and a room's listing (newest first) sorted all of its drops: both grew
    // with the room's history, on the event loop. The totals are now kept as
    // each drop settles, in the same transaction (records.js: DROP_SQL,
    // ROOM_STATS_SQL) and read in one lookup; drops_room_id serves a room's
    // drops in id order, so a page of them reads that page and no more.
    sql: `
CREATE TABLE room_buckets (
  room           TEXT NOT NULL,
  engine_version TEXT NOT NULL,
  bucket         SMALLINT NOT NULL,
  settled        BIGINT NOT NULL CHECK (settled > 0),
  bet            BIGINT NOT NULL CHECK (bet > 0),
  payout         BIGINT NOT NULL CHECK (payout >= 0),
  PRIMARY KEY (room, engine_version, bucket)
);
INSERT INTO room_buckets (room, engine_version, bucket, settled, bet, payout)
  SELECT room, engine_version, bucket, COUNT(*), SUM(bet), SUM(payout)
  FROM drops WHERE status = 'settled' GROUP BY room, engine_version, bucket;
DROP INDEX drops_room;
CREATE INDEX drops_room_id ON drops (room, id);
`
  },
  {
    version: 4,
    name: "a player's drops read through their seeds: no index of drops by player",
    // drops_player (player_id, id) was a write at a random place of the file
    // for each drop (the player's page of the index): 1.2 of a drop's 5.7
    // WAL pages and some 15% of the SQLite writer's CPU at 6,000 players
    // (loadtest/RESULTS.md). A player's drops, and a seed's, are now read
    // seed by seed through UNIQUE (server_seed_id, nonce), in the order they
    // were played (drop-pages.js); a player's seeds in that order, ties of
    // creation time by id, through server_seeds_order.
    sql: `
DROP INDEX drops_player;
CREATE INDEX server_seeds_order ON server_seeds (player_id, created_at, id);
DROP INDEX server_seeds_player;
`
  }
])

/** Statement creating the bookkeeping table (same in both databases). */
export const MIGRATIONS_TABLE = `
CREATE TABLE IF NOT EXISTS schema_migrations (
  version    INTEGER PRIMARY KEY,
  name       TEXT NOT NULL,
  applied_at BIGINT NOT NULL
)`
