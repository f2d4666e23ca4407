import { createBoard } from './board.js'
import { simulateDrop } from './drop-simulator.js'
import { deriveDropSeed, sha256Hex } from './fairness.js'
import { ENGINE_VERSION } from './version.js'

/**
 * Recomputes a drop from revealed seeds: the commitment, the drop seed and
 * the physics outcome, under the engine version the drop was decided under
 * (default: the newest). Anyone can run this after the server seed is revealed.
 * @param {{ serverSeed: string, clientSeed: string, nonce: number, rows?: number, risk?: string, engineVersion?: string }} input
 * @throws {import('./version.js').UnknownEngineVersionError} for a version this engine does not have
 */
export async function verifyDrop ({ serverSeed, clientSeed, nonce, rows = 16, risk = 'medium', engineVersion = ENGINE_VERSION }) {
  const board = createBoard({ rows, risk, engineVersion })
  const [serverSeedHash, dropSeed] = await Promise.all([
    sha256Hex(serverSeed),
    deriveDropSeed(serverSeed, clientSeed, nonce)
  ])
  const { bucket, multiplier, ticks, stateHash } = simulateDrop(board, dropSeed)
  return { serverSeedHash, dropSeed, bucket, multiplier, ticks, stateHash, engineVersion: board.engineVersion }
}
