import { createHash, createHmac, randomBytes } from 'node:crypto'
import { dropSeedMessage } from '../../engine/fairness.js'

/**
 * The server side of the provably-fair scheme, with node:crypto so the tick
 * loop never waits on a promise. The formulas are the engine's
 * (engine/fairness.js), which browsers run through WebCrypto:
 *   serverSeedHash = sha256_hex(serverSeed)
 *   dropSeed       = hmac_sha256_hex(key = serverSeed, message = clientSeed + ":" + nonce)
 */

import { CLIENT_SEED_PATTERN } from '../../protocol/client-messages.js'

export { CLIENT_SEED_PATTERN }
const clientSeedRegExp = new RegExp(CLIENT_SEED_PATTERN)

/** @param {string} text @returns {string} 64 hex digits */
export function sha256Hex (text) {
  return createHash('sha256').update(text).digest('hex')
}

/** @param {string} serverSeed @param {string} clientSeed @param {number} nonce */
export function deriveDropSeed (serverSeed, clientSeed, nonce) {
  return createHmac('sha256', serverSeed).update(dropSeedMessage(clientSeed, nonce)).digest('hex')
}

/** A fresh server seed (32 random bytes, hex) with its commitment and a row id. */
export function newServerSeed () {
  const seed = randomBytes(32).toString('hex')
  return { id: randomBytes(8).toString('hex'), seed, hash: sha256Hex(seed) }
}

/** Default client seed for a new player: the player may replace it at any time. */
export function newClientSeed () {
  return randomBytes(8).toString('hex')
}

/** @param {unknown} value */
export function isValidClientSeed (value) {
  return typeof value === 'string' && clientSeedRegExp.test(value)
}
