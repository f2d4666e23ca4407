import { wholeBatchCommitted, DROP_SQL, newDropValues, settlementValues } from './records.js'
import { immediateTransaction } from './sqlite-database.js'

/**
 * Every write of the SQLite ledger, as transactions prepared on one
 * connection: the tick's batch (new drops, settlements, credits, nonces,
 * client seeds), a new player with its first server seed, and a seed
 * rotation. Each takes the write lock up front (BEGIN IMMEDIATE) and is
 * committed whole or rolled back. The store runs them on its writer thread
 * (sqlite-writer-thread.js), so no write, and no wait for another
 * process's write lock, ever holds the event loop; an in-memory database,
 * which has no second connection, runs them on its own.
 * @param {import('node:sqlite').DatabaseSync} db
 */
export function prepareWrites (db) {
  const insertDrop = db.prepare(DROP_SQL.sqlite.insert)
  const settle = db.prepare(DROP_SQL.sqlite.settle)
  const credit = db.prepare('UPDATE players SET balance = balance + ? WHERE id = ?')
  const nonce = db.prepare('UPDATE server_seeds SET next_nonce = MAX(next_nonce, ?) WHERE id = ?')
  const clientSeed = db.prepare('UPDATE players SET client_seed = ? WHERE id = ?')
  const balanceOf = db.prepare('SELECT balance FROM players WHERE id = ?')
  const insertPlayer = db.prepare('INSERT INTO players (id, token_hash, balance, client_seed, created_at) VALUES (?, ?, ?, ?, ?)')
  const insertSeed = db.prepare('INSERT INTO server_seeds (id, player_id, seed, hash, active, next_nonce, created_at) VALUES (?, ?, ?, ?, 1, 0, ?)')
  const retireSeed = db.prepare('UPDATE server_seeds SET active = 0, revealed_at = ? WHERE id = ? AND player_id = ? AND active = 1')

  return {
    /**
     * Writes the batch whole or not at all; returns what it committed (one
     * process owns a SQLite ledger, so nothing is refused) and the touched
     * players' balances as committed.
     * @param {import('./records.js').LedgerBatch} batch
     * @returns {import('../game/money.js').CommitOutcome}
     */
    commitBatch: (batch) => immediateTransaction(db, () => {
      for (const d of batch.drops) insertDrop.run(...newDropValues(d))
      for (const s of batch.settlements) {
        if (settle.run(...settlementValues(s)).changes !== 1) throw new Error(`drop ${s.id} is not in flight; refusing to settle it twice`)
      }
      for (const b of batch.balances) {
        if (credit.run(b.delta, b.playerId).changes !== 1) throw new Error(`no player ${b.playerId}`)
      }
      for (const n of batch.nonces) nonce.run(n.nextNonce, n.seedId)
      for (const c of batch.clientSeeds) clientSeed.run(c.clientSeed, c.playerId)
      const balances = new Map()
      for (const playerId of batch.players ?? []) balances.set(playerId, Number(balanceOf.get(playerId)?.balance))
      return wholeBatchCommitted(batch, balances)
    }),
    createPlayer: ({ id, tokenHash, balance, clientSeed, createdAt, seed }) => immediateTransaction(db, () => {
      insertPlayer.run(id, tokenHash, balance, clientSeed, createdAt)
      insertSeed.run(seed.id, id, seed.seed, seed.hash, createdAt)
    }),
    rotateSeed: ({ playerId, oldSeedId, newSeed, at }) => immediateTransaction(db, () => {
      if (retireSeed.run(at, oldSeedId, playerId).changes !== 1) throw new Error(`seed ${oldSeedId} is not the active seed of ${playerId}`)
      insertSeed.run(newSeed.id, playerId, newSeed.seed, newSeed.hash, at)
    })
  }
}

/** The names of the writes prepareWrites() returns (what the writer thread accepts). */
export const WRITES = Object.freeze(['commitBatch', 'createPlayer', 'rotateSeed'])
