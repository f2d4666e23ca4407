/**
 * @typedef {{ playerId?: string, serverSeedHash?: string, nonce?: number, room?: string, status?: string,
 *   from?: number, to?: number, afterId?: number, beforeId?: number }} DropFilter times in ms
 */

/**
 * WHERE clause for drop queries, shared by both stores; `placeholder(n)`
 * returns the n-th (1-based) parameter marker: '?' for SQLite, '$n' for
 * PostgreSQL. Columns belong to the alias `d` (drops).
 * @param {DropFilter} filter
 * @param {(n: number) => string} placeholder
 */
export function dropFilterSql (filter, placeholder) {
  const clauses = []
  const params = []
  const add = (sql, value) => { params.push(value); clauses.push(sql.replace('?', placeholder(params.length))) }
  if (filter.playerId !== undefined) add('d.player_id = ?', filter.playerId)
  if (filter.serverSeedHash !== undefined) {
    // The seed's player too (a seed is one player's): the pages in id order then walk that
    // player's drops (drops_player) instead of sorting every drop of the seed for each page,
    // which made an export of a seed cost its drops squared. A nonce still goes through
    // UNIQUE (server_seed_id, nonce). No index on the long hash in drops.
    add('d.player_id = (SELECT player_id FROM server_seeds WHERE hash = ?)', filter.serverSeedHash)
    add('d.server_seed_id = (SELECT id FROM server_seeds WHERE hash = ?)', filter.serverSeedHash)
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
