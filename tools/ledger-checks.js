import pg from 'pg'

/**
 * Checks of a PostgreSQL ledger from outside the server, for the cluster
 * tests and the load-test cluster smoke.
 */

/** One query on a database URL. */
export async function query (url, sql, params = []) {
  const client = new pg.Client({ connectionString: url })
  await client.connect()
  try {
    return (await client.query(sql, params)).rows
  } finally {
    await client.end()
  }
}

/**
 * Every player's balance equals start - bets + payouts (the ledger holds
 * balances and payouts in milli-credits, bets in whole credits).
 * @param {string} url @param {number} startingBalance credits
 */
export async function ledgerMismatches (url, startingBalance) {
  return query(url, `SELECT p.id, p.balance,
      $1::bigint * 1000 - COALESCE(SUM(d.bet), 0) * 1000 + COALESCE(SUM(d.payout), 0) AS expected
    FROM players p LEFT JOIN drops d ON d.player_id = p.id
    GROUP BY p.id, p.balance
    HAVING p.balance <> $1::bigint * 1000 - COALESCE(SUM(d.bet), 0) * 1000 + COALESCE(SUM(d.payout), 0)`, [startingBalance])
}

