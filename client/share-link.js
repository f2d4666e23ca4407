import { sha256Hex } from '/engine/index.js'

/** Hex characters of a share token (server/routes/share.js, SHARE_TOKEN_LENGTH). */
const TOKEN_LENGTH = 20

/** The path of a drop's share page. @param {number} dropId @param {string} hash sha256("share:" + drop seed), hex */
export function shareLinkPath (dropId, hash) {
  return `/share/${dropId}/${hash.slice(0, TOKEN_LENGTH)}`
}

/**
 * A drop's share link, from its drop seed (only its player sees it before
 * sharing), as server/routes/share.js checks it.
 * @param {{ id: number, dropSeed: string }} record
 */
export async function shareLink ({ id, dropSeed }) {
  return new URL(shareLinkPath(id, await sha256Hex(`share:${dropSeed}`)), location.href).href
}
