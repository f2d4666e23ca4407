import { sha256Hex } from '/engine/index.js'
import { shareTokenMessage, shareTokenOf } from '/protocol/share-token.js'

/**
 * A drop's share token (protocol/share-token.js), hashed with WebCrypto:
 * the page's one copy of the rule server/routes/share.js checks. Anyone
 * with the drop seed can compute it: the player, and the players of its
 * room, to whom the seed was announced.
 * @param {string} dropSeed
 */
export async function shareToken (dropSeed) {
  return shareTokenOf(await sha256Hex(shareTokenMessage(dropSeed)))
}

/** The path of a drop's share page. @param {number} dropId @param {string} token its share token */
export function shareLinkPath (dropId, token) {
  return `/share/${dropId}/${token}`
}

/** The API path of a shared drop (GET /api/share/:id/:token). @param {number | string} dropId @param {string} token */
export function sharedDropPath (dropId, token) {
  return `/api/share/${dropId}/${token}`
}

/**
 * A drop's share link, from its drop seed, as server/routes/share.js checks it.
 * @param {{ id: number, dropSeed: string }} record
 */
export async function shareLink ({ id, dropSeed }) {
  return new URL(shareLinkPath(id, await shareToken(dropSeed)), location.href).href
}
