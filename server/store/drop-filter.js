/**
 * @typedef {{ playerId?: string, serverSeedHash?: string, nonce?: number, room?: string, status?: string,
 *   from?: number, to?: number, afterId?: number, beforeId?: number }} DropFilter times in ms
 */

/**
 * The seed a filter names by its hash, as its drops are found: its id and
 * its player (one statement per dialect). A store reads it first and hands
 * it to dropFilterSql; no row: no seed, no drops.
 */
export const SEED_OF_HASH_SQL = Object.freeze({
  sqlite: 'SELECT id, player_id FROM server_seeds WHERE hash = ?',
  postgres: 'SELECT id, player_id FROM server_seeds WHERE hash = $1'
})

/**
 * WHERE clause for drop queries, shared by both stores; `placeholder(n)`
 * returns the n-th (1-based) parameter marker: '?' for SQLite, '$n' for
 * PostgreSQL. Columns belong to the alias `d` (drops).
 * @param {DropFilter} filter
 * @param {(n: number) => string} placeholder
 * @param {{ id: string, player_id: string }} [seed] the seed `filter.serverSeedHash` names (SEED_OF_HASH_SQL's row), read first
 */
export function dropFilterSql (filter, placeholder, seed) {
  const clauses = []
  const params = []
  const add = (sql, value) => { params.push(value); clauses.push(sql.replace('?', placeholder(params.length))) }
  if (filter.playerId !== undefined) add('d.player_id = ?', filter.playerId)
  if (filter.serverSeedHash !== undefined) {
    if (!seed) throw new Error('dropFilterSql: read the seed of filter.serverSeedHash first (SEED_OF_HASH_SQL)')
    // The seed's player and id as values: a page in id order then walks that player's drops
    // (drops_player) or the ids from the cursor on, in both databases, instead of sorting every
    // drop of the seed for each page (an export of a seed cost its drops squared; given the
    // player by a subquery, PostgreSQL still sorted them: 380 ms a page at 125,500 drops).
    // A nonce still goes through UNIQUE (server_seed_id, nonce).
    add('d.player_id = ?', seed.player_id)
    add('d.server_seed_id = ?', seed.id)
  }
  if (filter.nonce !== undefined) add('d.nonce = ?', filter.nonce)
  if (filter.room !== undefined) add('d.room = ?', filter.room)
  if (filter.status !== undefined) add('d.status = ?', filter.status)
  if (filter.from !== undefined) add('d.created_at >= ?', filter.from)
  if (filter.to !== undefined) add('d.created_at < ?', filter.to)
  if (filter.afterId !== undefined) add('d.id > ?', filter.afterId)
  if (filter.beforeId !== undefined) add('d.id < ?', filter.beforeId)
  return { where: clauses.length ? 'WHERE ' + clauses.join(' AND ') : '', params }
}
