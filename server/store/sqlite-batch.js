/**
 * One ledger batch on SQLite: the tick's new drops, settlements, credits,
 * nonces and client seeds in one transaction (run it `.immediate(batch)`,
 * so it takes the write lock up front). Shared by the store, for an
 * in-memory database, and by its writer thread (sqlite-writer-thread.js).
 * @param {import('better-sqlite3').Database} db
 * @returns {import('better-sqlite3').Transaction<(batch: import('./records.js').LedgerBatch) => void>}
 */
export function prepareBatchCommit (db) {
  const insert = db.prepare(`INSERT INTO drops (id, player_id, room, rows, risk, engine_version, server_seed_id,
      server_seed_hash, client_seed, nonce, drop_seed, bet, start_tick, status, created_at)
    VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 'in_flight', ?)`)
  const settle = db.prepare(`UPDATE drops SET status = 'settled', bucket = ?, multiplier = ?, payout = ?,
      ticks = ?, state_hash = ?, settled_at = ? WHERE id = ? AND status = 'in_flight'`)
  const credit = db.prepare('UPDATE players SET balance = balance + ? WHERE id = ?')
  const nonce = db.prepare('UPDATE server_seeds SET next_nonce = MAX(next_nonce, ?) WHERE id = ?')
  const clientSeed = db.prepare('UPDATE players SET client_seed = ? WHERE id = ?')
  return db.transaction((batch) => {
    for (const d of batch.drops) {
      insert.run(d.id, d.playerId, d.room, d.rows, d.risk, d.engineVersion, d.serverSeedId,
        d.serverSeedHash, d.clientSeed, d.nonce, d.dropSeed, d.bet, d.startTick, d.createdAt)
    }
    for (const s of batch.settlements) {
      const { changes } = settle.run(s.bucket, s.multiplier, s.payout, s.ticks, s.stateHash, s.settledAt, s.id)
      if (changes !== 1) throw new Error(`drop ${s.id} is not in flight; refusing to settle it twice`)
    }
    for (const b of batch.balances) {
      if (credit.run(b.delta, b.playerId).changes !== 1) throw new Error(`no player ${b.playerId}`)
    }
    for (const n of batch.nonces) nonce.run(n.nextNonce, n.seedId)
    for (const c of batch.clientSeeds) clientSeed.run(c.clientSeed, c.playerId)
  })
}
