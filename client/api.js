/**
 * HTTP calls to the server's JSON API. Every failure becomes an ApiError
 * carrying the server's named code (E_UNAUTHORIZED, E_NOT_FOUND, …), or
 * E_NETWORK when the server could not be reached.
 */

export class ApiError extends Error {
  /** @param {string} code @param {string} message @param {number} status 0 when nothing answered */
  constructor (code, message, status) {
    super(message)
    this.name = 'ApiError'
    this.code = code
    this.status = status
  }
}

/**
 * @param {string} method
 * @param {string} path
 * @param {{ token?: string | null, body?: any }} [options] token: sent as Authorization: Bearer
 * @returns {Promise<any>} the parsed JSON reply
 */
export async function apiRequest (method, path, { token, body } = {}) {
  const headers = {}
  if (token) headers.authorization = `Bearer ${token}`
  if (body !== undefined) headers['content-type'] = 'application/json'
  let response
  try {
    response = await fetch(path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body), cache: 'no-store' })
  } catch (error) {
    throw new ApiError('E_NETWORK', `server unreachable: ${error.message}`, 0)
  }
  const text = await response.text()
  let json = null
  try {
    json = text === '' ? null : JSON.parse(text)
  } catch {}
  if (!response.ok) {
    throw new ApiError(json?.code ?? `HTTP_${response.status}`, json?.message ?? (text.slice(0, 200) || response.statusText), response.status)
  }
  return json
}

/** Builds a query string from defined, non-empty values. @param {Record<string, any>} params */
export function query (params) {
  const search = new URLSearchParams()
  for (const [name, value] of Object.entries(params)) {
    if (value !== undefined && value !== null && value !== '') search.set(name, String(value))
  }
  const text = search.toString()
  return text === '' ? '' : `?${text}`
}
