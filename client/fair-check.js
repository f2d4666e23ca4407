import { createBoard, simulateDrop, sha256Hex, deriveDropSeed } from '/engine/index.js'

/**
 * The whole provably-fair chain for one drop, recomputed in the browser
 * with the engine's own functions (WebCrypto for the hashes):
 *   sha256(serverSeed)                      = the commitment shown before the drop
 *   HMAC-SHA256(serverSeed, clientSeed:nonce) = the drop seed
 *   simulate(board, drop seed)              = the recorded bucket, ticks and final state,
 * under the engine version the drop was decided under (default the newest).
 */

/**
 * @typedef {object} FairCheck
 * @property {number | null} dropId
 * @property {string} serverSeedHash recomputed @property {string} dropSeed recomputed
 * @property {number} bucket @property {number} ticks @property {string} stateHash @property {number} multiplier recomputed
 * @property {Record<string, boolean | null>} checks each link against the record (null: nothing recorded to compare)
 * @property {boolean} ok every applicable check passed
 */

/**
 * @param {{ serverSeed: string, clientSeed: string, nonce: number, rows: number, risk: string, engineVersion?: string }} seeds
 * @param {{ id?: number, serverSeedHash?: string, dropSeed?: string, bucket?: number | null, ticks?: number | null, stateHash?: string | null }} [record]
 *   what the server recorded or announced, to compare with
 * @returns {Promise<FairCheck>}
 */
export async function checkFairness ({ serverSeed, clientSeed, nonce, rows, risk, engineVersion }, record = {}) {
  const [serverSeedHash, dropSeed] = await Promise.all([sha256Hex(serverSeed), deriveDropSeed(serverSeed, clientSeed, nonce)])
  const board = createBoard({ rows, risk, engineVersion })
  const outcome = simulateDrop(board, dropSeed)
  const compare = (recorded, computed) => (recorded === undefined || recorded === null ? null : recorded === computed)
  const checks = {
    commitment: compare(record.serverSeedHash, serverSeedHash),
    dropSeed: compare(record.dropSeed, dropSeed),
    bucket: compare(record.bucket, outcome.bucket),
    ticks: compare(record.ticks, outcome.ticks),
    stateHash: compare(record.stateHash, outcome.stateHash)
  }
  return {
    dropId: record.id ?? null,
    engineVersion: board.engineVersion,
    serverSeedHash,
    dropSeed,
    bucket: outcome.bucket,
    ticks: outcome.ticks,
    stateHash: outcome.stateHash,
    multiplier: outcome.multiplier,
    checks,
    ok: Object.values(checks).every((check) => check !== false)
  }
}
