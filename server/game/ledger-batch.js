import { balanceChanges } from './money.js'
import { newDropRow, settlementRow } from './drop.js'

/**
 * The rows one batch writes: new drops, settlements, one net balance change
 * per player (money.js), the highest nonce used per seed, client seeds
 * changed by `drop {clientSeed}`, and every player the batch touches (whose
 * committed balances the store returns).
 * @param {{ drops: import('./drop.js').Drop[], settlements: import('./drop.js').Settlement[] }} batch
 * @returns {import('../store/records.js').LedgerBatch}
 */
export function toLedgerBatch ({ drops, settlements }) {
  const nonces = new Map()
  const clientSeeds = new Map()
  for (const drop of drops) {
    nonces.set(drop.seedId, Math.max(nonces.get(drop.seedId) ?? 0, drop.nonce + 1))
    if (drop.clientSeedChange) clientSeeds.set(drop.playerId, drop.clientSeed)
  }
  const changes = balanceChanges(drops, settlements)
  return {
    drops: drops.map(newDropRow),
    settlements: settlements.map(settlementRow),
    balances: [...changes].filter(([, delta]) => delta !== 0).map(([playerId, delta]) => ({ playerId, delta })),
    nonces: [...nonces].map(([seedId, nextNonce]) => ({ seedId, nextNonce })),
    clientSeeds: [...clientSeeds].map(([playerId, clientSeed]) => ({ playerId, clientSeed })),
    players: [...changes.keys()]
  }
}

/** A batch that only sets a player's client seed (`POST /api/seeds/client`). @returns {import('../store/records.js').LedgerBatch} */
export function clientSeedBatch (playerId, clientSeed) {
  return { drops: [], settlements: [], balances: [], nonces: [], clientSeeds: [{ playerId, clientSeed }], players: [] }
}
