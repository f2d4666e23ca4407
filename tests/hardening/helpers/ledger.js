import { createBoard, simulateDrop } from '../../../engine/index.js'
import { payoutFor } from '../../../server/game/money.js'

/**
 * Cross-checks of the ledger read straight from the database (bypassing
 * the server): counts for "nothing changed", and the full consistency
 * check "every drop settled from its seed, every balance equals start +
 * payouts − bets". The ledger holds balances and payouts in milli-credits,
 * bets in whole credits; starting balances are given in credits.
 */

/** Drops, settled drops and the sum of all balances net of starting balances (new players change nothing). */
export async function ledgerTotals (backend, database, startingBalance = 100000) {
  const [drops] = await backend.query(database, "SELECT COUNT(*) AS n, SUM(CASE WHEN status = 'settled' THEN 1 ELSE 0 END) AS settled FROM drops")
  const [players] = await backend.query(database, 'SELECT COUNT(*) AS n, COALESCE(SUM(balance), 0) AS total FROM players')
  return { drops: Number(drops.n), settled: Number(drops.settled ?? 0), net: Number(players.total) - Number(players.n) * startingBalance * 1000 }
}

/**
 * Checks every drop in the ledger against a fresh simulation of its seed,
 * and every listed player's balance against start + payouts − bets.
 * Returns the drops by id, for further checks.
 * @param {{ query: Function }} backend
 * @param {any} database
 * @param {{ playerIds: string[], startingBalance: number }} options
 */
export async function expectConsistentLedger (expect, backend, database, { playerIds, startingBalance }) {
  const rows = await backend.query(database, 'SELECT id, player_id, rows, risk, engine_version, drop_seed, bet, status, bucket, payout, payout_rule FROM drops ORDER BY id')
  const boards = new Map()
  const perPlayer = new Map(playerIds.map((id) => [id, startingBalance * 1000]))
  const byId = new Map()
  for (const row of rows) {
    const id = Number(row.id)
    expect(byId.has(id), `drop ${id} appears once`).toBe(false)
    const key = `${row.rows}-${row.risk}@${row.engine_version}`
    if (!boards.has(key)) boards.set(key, createBoard({ rows: Number(row.rows), risk: row.risk, engineVersion: row.engine_version }))
    const outcome = simulateDrop(boards.get(key), row.drop_seed)
    const bet = Number(row.bet)
    expect(row.status, `drop ${id} settled`).toBe('settled')
    expect(Number(row.bucket), `drop ${id} bucket`).toBe(outcome.bucket)
    expect(Number(row.payout), `drop ${id} payout`).toBe(payoutFor(bet, outcome.multiplier, Number(row.payout_rule)))
    if (perPlayer.has(row.player_id)) perPlayer.set(row.player_id, perPlayer.get(row.player_id) - bet * 1000 + Number(row.payout))
    byId.set(id, { id, playerId: row.player_id, bet, payout: Number(row.payout) })
  }
  for (const [playerId, expected] of perPlayer) {
    const [player] = await backend.query(database, 'SELECT balance FROM players WHERE id = $1', [playerId])
    expect(Number(player.balance), `balance of ${playerId}`).toBe(expected)
  }
  return byId
}
