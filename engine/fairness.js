/**
 * Provably fair seed derivation, identical in Node 20 and browsers through
 * WebCrypto (globalThis.crypto.subtle):
 *   serverSeedHash = sha256_hex(serverSeed)
 *   dropSeed       = hmac_sha256_hex(key = serverSeed, message = clientSeed + ":" + nonce)
 * Seeds are UTF-8 strings; the nonce is a non-negative integer in decimal.
 * Browsers expose WebCrypto only in secure contexts (https or localhost).
 */

// Created on first use: plain JavaScript engines (QuickJS) have no
// TextEncoder, and must still be able to load the engine to simulate.
let encoder = null
function utf8 (text) {
  encoder ??= new TextEncoder()
  return encoder.encode(text)
}

function subtle () {
  const subtleCrypto = globalThis.crypto?.subtle
  if (!subtleCrypto) {
    throw new Error('WebCrypto is not available here (browsers provide it only on https:// or localhost pages)')
  }
  return subtleCrypto
}

function toHex (buffer) {
  const bytes = new Uint8Array(buffer)
  let hex = ''
  for (let i = 0; i < bytes.length; i++) hex += (bytes[i] < 16 ? '0' : '') + bytes[i].toString(16)
  return hex
}

/** @param {string} text @returns {Promise<string>} 64 hex digits */
export async function sha256Hex (text) {
  return toHex(await subtle().digest('SHA-256', utf8(text)))
}

/** @param {string} key @param {string} message @returns {Promise<string>} 64 hex digits */
export async function hmacSha256Hex (key, message) {
  const keyBytes = utf8(key)
  if (keyBytes.length === 0) throw new RangeError('HMAC key must not be empty')
  const cryptoKey = await subtle().importKey('raw', keyBytes, { name: 'HMAC', hash: 'SHA-256' }, false, ['sign'])
  return toHex(await subtle().sign('HMAC', cryptoKey, utf8(message)))
}

/**
 * The HMAC message for a drop: clientSeed + ":" + nonce.
 * @param {string} clientSeed @param {number} nonce
 */
export function dropSeedMessage (clientSeed, nonce) {
  if (typeof clientSeed !== 'string') throw new TypeError('clientSeed must be a string')
  if (!Number.isSafeInteger(nonce) || nonce < 0) throw new RangeError('nonce must be a non-negative safe integer')
  return clientSeed + ':' + nonce
}

/**
 * @param {string} serverSeed @param {string} clientSeed @param {number} nonce
 * @returns {Promise<string>} the drop seed, 64 hex digits
 */
export async function deriveDropSeed (serverSeed, clientSeed, nonce) {
  if (typeof serverSeed !== 'string' || serverSeed.length === 0) throw new TypeError('serverSeed must be a non-empty string')
  return hmacSha256Hex(serverSeed, dropSeedMessage(clientSeed, nonce))
}
