/**
 * @typedef {{ playerId?: string, serverSeedHash?: string, nonce?: number, room?: string, status?: string,
 *   from?: number, to?: number, afterId?: number, beforeId?: number }} DropFilter times in ms
 */

/**
 * WHERE clause for drop queries, shared by both stores; `placeholder(n)`
 * returns the n-th (1-based) parameter marker: '?' for SQLite, '$n' for
 * PostgreSQL. Columns belong to the alias `d` (drops). Every condition
 * but the player and the seed: a player's and a seed's drops are read seed
 * by seed (drop-pages.js), each seed's condition among `leading`.
 * @param {DropFilter} filter
 * @param {(n: number) => string} placeholder
 * @param {{ sql: string, value: any }[]} [leading] conditions before the filter's, each with one `?`
 */
export function dropFilterSql (filter, placeholder, leading = []) {
  const clauses = []
  const params = []
  const add = (sql, value) => { params.push(value); clauses.push(sql.replace('?', placeholder(params.length))) }
  for (const { sql, value } of leading) add(sql, value)
  if (filter.nonce !== undefined) add('d.nonce = ?', filter.nonce)
  if (filter.room !== undefined) add('d.room = ?', filter.room)
  if (filter.status !== undefined) add('d.status = ?', filter.status)
  if (filter.from !== undefined) add('d.created_at >= ?', filter.from)
  if (filter.to !== undefined) add('d.created_at < ?', filter.to)
  if (filter.afterId !== undefined) add('d.id > ?', filter.afterId)
  if (filter.beforeId !== undefined) add('d.id < ?', filter.beforeId)
  return { where: clauses.length ? 'WHERE ' + clauses.join(' AND ') : '', params }
}
