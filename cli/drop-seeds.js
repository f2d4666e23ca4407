import { createHmac } from 'node:crypto'
import { dropSeedMessage } from '../engine/fairness.js'

/**
 * Synchronous drop-seed derivation for batch tools (Node only): the same
 * HMAC-SHA256 as engine/fairness.js, without a promise per drop.
 * @param {string} serverSeed @param {string} clientSeed @param {number} nonce
 */
export function dropSeedSync (serverSeed, clientSeed, nonce) {
  return createHmac('sha256', serverSeed).update(dropSeedMessage(clientSeed, nonce)).digest('hex')
}
