/**
 * The game socket's URL for a session token (the wire format itself is
 * /protocol/, shared with the server).
 */

/**
 * The game socket's URL for a session token. `base` is where the socket
 * lives: the page's own address (its directory, so a page served under a
 * prefix such as /n/1/ talks to that process) or, after E_WRONG_NODE, the
 * `owner` the server named. Only http(s) bases are followed; anything else
 * gives null.
 * @param {string} base an absolute http(s) URL
 * @param {string} token
 * @returns {string | null}
 */
export function socketUrl (base, token) {
  let url
  try {
    url = new URL(base)
  } catch {
    return null
  }
  if (url.protocol !== 'http:' && url.protocol !== 'https:') return null
  url.protocol = url.protocol === 'https:' ? 'wss:' : 'ws:'
  url.pathname = url.pathname.replace(/\/?$/, '/') + 'ws'
  url.search = `?token=${encodeURIComponent(token)}`
  url.hash = ''
  return url.href
}
