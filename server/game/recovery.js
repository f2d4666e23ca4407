import { isEngineVersion, simulateDrop } from '../../engine/index.js'
import { parseRoomId, roomIdOf } from '../../protocol/room-id.js'
import { boardOf } from '../rooms/boards.js'
import { toLedgerBatch } from './drop.js'
import { payoutFor } from './money.js'

/**
 * Start-up recovery: drops still in flight in the ledger were recorded and
 * debited, but the process stopped before they landed. A drop's outcome is
 * fixed by its seed and board, so each is played to the end now and settled
 * exactly as the room would have settled it, all in one transaction, under
 * the engine version it was recorded under (a drop in flight across an
 * upgrade settles under the old version). A drop of a version this engine
 * does not have (recorded by a newer server, then rolled back) is left in
 * flight for a server that has it, and logged.
 * @param {any} store
 * @param {{ info: Function, warn: Function, error: Function }} log
 * @param {{ drops?: object[] }} [options] only these drops (as listInFlightDrops returns them)
 * @returns {Promise<{ settled: number, skipped: number }>}
 */
export async function settleInterruptedDrops (store, log, { drops } = {}) {
  // A clustered process passes the drops of one room it has just taken over (server/cluster/).
  drops ??= await store.listInFlightDrops()
  if (drops.length === 0) return { settled: 0, skipped: 0 }
  const settlements = []
  let skipped = 0
  for (const drop of drops) {
    const roomId = roomIdOf(drop.rows, drop.risk)
    if (!isEngineVersion(drop.engineVersion) || !parseRoomId(roomId)) {
      skipped++
      log.error({ dropId: drop.id, engineVersion: drop.engineVersion }, 'cannot replay an interrupted drop recorded under an engine version this server does not have; left in flight')
      continue
    }
    const outcome = simulateDrop(boardOf(roomId, drop.engineVersion), drop.dropSeed)
    const payout = payoutFor(drop.bet, outcome.multiplier, drop.payoutRule)
    settlements.push({ drop, bucket: outcome.bucket, multiplier: outcome.multiplier, payout, ticks: outcome.ticks, stateHash: outcome.stateHash, settledAt: Date.now() })
  }
  let result
  if (settlements.length > 0) {
    // The shared ledger (cluster) settles only drops still in flight and says which.
    result = await store.commitBatch(toLedgerBatch({ drops: [], settlements }))
  }
  const settled = result ? result.settled.size : 0
  log.warn({ settled, skipped }, 'settled drops interrupted by the last shutdown')
  return { settled, skipped }
}
