/**
 * A drop's share token, one rule for the server and the browser (served at
 * /protocol/): the first SHARE_TOKEN_LENGTH hex characters of
 *   sha256_hex("share:" + dropSeed)
 * (UTF-8). Whoever has a drop's seed can make its token: the player, and
 * everyone in its room (the seed is announced there); nobody can walk the
 * ids. GET /api/share/:id/:token answers only with the right token.
 *
 * The hash is the caller's (node:crypto on the server, synchronous;
 * WebCrypto in a browser), so this module imports neither.
 */

/** Hex characters of a share token. */
export const SHARE_TOKEN_LENGTH = 20

/** What is hashed for a drop's share token. @param {string} dropSeed */
export function shareTokenMessage (dropSeed) {
  return `share:${dropSeed}`
}

/** The share token, from the SHA-256 of shareTokenMessage(dropSeed). @param {string} sha256Hex 64 hex digits */
export function shareTokenOf (sha256Hex) {
  return sha256Hex.slice(0, SHARE_TOKEN_LENGTH)
}

