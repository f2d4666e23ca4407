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

/**
 * Every room's totals by bucket (room_buckets, kept as each drop settles)
 * equal the sums over its settled drops: the rows where they differ, or a
 * side has none.
 * @param {string} url
 */
export async function roomTotalMismatches (url) {
  return query(url, `SELECT COALESCE(t.room, s.room) AS room, COALESCE(t.engine_version, s.engine_version) AS engine_version,
      COALESCE(t.bucket, s.bucket) AS bucket, t.settled, s.settled AS expected_settled, t.bet, s.bet AS expected_bet, t.payout, s.payout AS expected_payout
    FROM room_buckets t FULL OUTER JOIN (
      SELECT room, engine_version, bucket, COUNT(*) AS settled, SUM(bet) AS bet, SUM(payout) AS payout
      FROM drops WHERE status = 'settled' GROUP BY room, engine_version, bucket
    ) s ON s.room = t.room AND s.engine_version = t.engine_version AND s.bucket = t.bucket
    WHERE t.settled IS DISTINCT FROM s.settled OR t.bet IS DISTINCT FROM s.bet OR t.payout IS DISTINCT FROM s.payout`)
}
