import { dropFilterSql } from './drop-filter.js'
import { gameError } from '../errors.js'
import { DROP_COLUMNS_WITH_REVEALED_SEED, toDropRecord } from './records.js'

/**
 * A page of the drops a filter matches, in either dialect, as a sequence
 * of statements: the store drives it (driveDropsPage, driveDropsPageAsync),
 * running each statement it yields and handing back the rows, so that
 * both stores page by the same rule.
 *
 * - A player's drops, or one seed's, are listed in the order they were
 *   played: seed by seed (in the order the seeds were created), nonce by
 *   nonce within a seed. They are read seed by seed through UNIQUE
 *   (server_seed_id, nonce), the index that keeps a nonce from being used
 *   twice: no index by player is written for each drop (migration 4 dropped
 *   drops_player, a write at a random place of the file per drop). In one
 *   process this is the order of the drops' ids; in a cluster a player's
 *   drops may take ids from several processes' blocks, and play order is
 *   the one that tells their history.
 *   The cursor (beforeId newest first, afterId oldest first) names the last
 *   drop of the previous page; a page goes on after it. A cursor that is
 *   not one of the player's (or the seed's) drops has no place in that
 *   order: the page is null, and the store refuses the listing
 *   (listedPage). Bounding the ids instead would read every drop of
 *   a seed past the cursor, for each page.
 * - Any other filter (room, time, none) is one statement in id order.
 *
 * @param {import('./drop-filter.js').DropFilter} filter
 * @param {'ASC' | 'DESC'} order DESC: newest first (listings, cursor beforeId); ASC: oldest first (an export's pages, cursor afterId)
 * @param {number} limit
 * @param {'sqlite' | 'postgres'} dialect
 * @returns {Generator<{ sql: string, params: any[] }, object[] | null, any[]>} yields statements, takes their rows,
 *   returns drop records (null: the cursor is not one of the listed drops)
 */
export function * dropsPage (filter, order, limit, dialect) {
  const placeholder = dialect === 'sqlite' ? () => '?' : (n) => '$' + n
  if (filter.playerId === undefined && filter.serverSeedHash === undefined) {
    const { where, params } = dropFilterSql(filter, placeholder)
    const rows = yield { sql: pageSql(where, `d.id ${order}`, placeholder(params.length + 1)), params: [...params, limit] }
    return rows.map(toDropRecord)
  }

  const sqliteIndex = dialect === 'sqlite' ? SQLITE_SEED_NONCE_INDEX : ''
  // Past the cursor in the walk's order: below it newest first, above it oldest first.
  const past = order === 'DESC' ? '<' : '>'
  // The filter's other conditions (room, status, nonce, time) apply within each seed; the cursor is placed by the walk.
  const rest = { ...filter, beforeId: undefined, afterId: undefined }
  const drops = []
  /** One seed's drops for the page, after `afterNonce` if given. */
  const readSeed = function * (seedId, afterNonce) {
    const leading = [{ sql: 'd.server_seed_id = ?', value: seedId }]
    if (afterNonce !== undefined) leading.push({ sql: `d.nonce ${past} ?`, value: afterNonce })
    const { where, params } = dropFilterSql(rest, placeholder, leading)
    const rows = yield { sql: pageSql(where, `d.nonce ${order}`, placeholder(params.length + 1), sqliteIndex), params: [...params, limit - drops.length] }
    for (const row of rows) drops.push(toDropRecord(row))
  }

  // The cursor: where in this walk the previous page ended.
  const cursor = order === 'DESC' ? filter.beforeId : filter.afterId
  if (filter.serverSeedHash !== undefined) {
    // The seed, and the cursor's nonce if the cursor is one of its drops: one statement.
    const [seed] = yield {
      sql: `SELECT s.id, s.player_id, (SELECT d.nonce FROM drops d WHERE d.id = ${placeholder(1)} AND d.server_seed_id = s.id) AS cursor_nonce
        FROM server_seeds s WHERE s.hash = ${placeholder(2)}`,
      params: [cursor ?? null, filter.serverSeedHash]
    }
    if (!seed || (filter.playerId !== undefined && seed.player_id !== filter.playerId)) return []
    if (cursor !== undefined && seed.cursor_nonce === null) return null
    yield * readSeed(seed.id, seed.cursor_nonce === null ? undefined : Number(seed.cursor_nonce))
    return drops
  }
  /** @type {{ id: string, created_at: number } | null} the last seed read: the walk goes on after it */
  let lastSeed = null
  if (cursor !== undefined) {
    const [at] = yield {
      sql: `SELECT d.nonce, s.id, s.created_at FROM drops d JOIN server_seeds s ON s.id = d.server_seed_id
        WHERE d.id = ${placeholder(1)} AND s.player_id = ${placeholder(2)}`,
      params: [cursor, filter.playerId]
    }
    if (!at) return null
    yield * readSeed(at.id, Number(at.nonce))
    lastSeed = at
  }
  // A player's seeds, a few at a time from where the walk is, each read until the page is full.
  for (;;) {
    if (drops.length >= limit) return drops
    const afterLast = lastSeed ? ` AND (created_at, id) ${past} (${placeholder(2)}, ${placeholder(3)})` : ''
    const seeds = yield {
      sql: `SELECT id, created_at FROM server_seeds WHERE player_id = ${placeholder(1)}${afterLast}
        ORDER BY created_at ${order}, id ${order} LIMIT ${SEEDS_A_READ}`,
      params: lastSeed ? [filter.playerId, lastSeed.created_at, lastSeed.id] : [filter.playerId]
    }
    for (const next of seeds) {
      if (drops.length >= limit) return drops
      yield * readSeed(next.id)
      lastSeed = next
    }
    if (seeds.length < SEEDS_A_READ) return drops
  }
}

/**
 * A page as the API gives it: a null page (its cursor is none of the
 * listed drops) is refused with E_NOT_FOUND, whether the cursor is another
 * player's drop or no drop at all (as GET /api/drops/:id answers: ids
 * cannot be counted).
 * @param {object[] | null} page @param {number | undefined} cursor the page's beforeId or afterId
 */
export function listedPage (page, cursor) {
  if (page === null) throw gameError('E_NOT_FOUND', `no drop ${cursor} among the listed drops: before must be the id of the previous page's last drop`)
  return page
}

/** A player's seeds read at a time by a listing of their drops (most players have one). */
const SEEDS_A_READ = 16

/**
 * SQLite's name for the index of UNIQUE (server_seed_id, nonce): the second
 * constraint of the drops table that needs one, after its primary key. Named
 * so that a room or a time bound in the same filter cannot draw SQLite to
 * another index and a sort of the seed's drops (tests/server/ledger-query-plans.test.js
 * checks that it exists and is the one).
 */
export const SQLITE_SEED_NONCE_INDEX = 'INDEXED BY sqlite_autoindex_drops_2'

/** A page's statement: the drops (with the seed where revealed) in `orderBy`. */
function pageSql (where, orderBy, limit, index = '') {
  return `SELECT ${DROP_COLUMNS_WITH_REVEALED_SEED} FROM drops d ${index}
    JOIN server_seeds s ON s.id = d.server_seed_id ${where} ORDER BY ${orderBy} LIMIT ${limit}`
}

/**
 * Runs dropsPage on a synchronous connection (SQLite's).
 * @param {Generator<{ sql: string, params: any[] }, object[], any[]>} page
 * @param {(sql: string, params: any[]) => any[]} all a statement's rows
 */
export function driveDropsPage (page, all) {
  let step = page.next()
  while (!step.done) step = page.next(all(step.value.sql, step.value.params))
  return step.value
}

/**
 * Runs dropsPage on an asynchronous connection (PostgreSQL's).
 * @param {Generator<{ sql: string, params: any[] }, object[], any[]>} page
 * @param {(sql: string, params: any[]) => Promise<any[]>} all a statement's rows
 */
export async function driveDropsPageAsync (page, all) {
  let step = page.next()
  while (!step.done) step = page.next(await all(step.value.sql, step.value.params))
  return step.value
}
