import { apiRequest, ApiError } from './api.js'

/** localStorage key of the guest session: { token, playerId }. */
export const SESSION_KEY = 'plinko.session'

/**
 * @typedef {object} Me what GET /api/me returns
 * @property {string} playerId @property {number} balance
 * @property {string} serverSeedHash @property {string} clientSeed @property {number} nonce
 */

/**
 * The guest session kept in localStorage across reloads and reconnects.
 * A stored token the server no longer knows (a wiped database) is replaced
 * by a new guest session.
 */
export class Session {
  constructor (storage = globalThis.localStorage) {
    this.storage = storage
    /** @type {string | null} */
    this.token = null
    /** @type {string | null} */
    this.playerId = null
  }

  /**
   * Loads the stored session and checks it with GET /api/me, or creates a
   * new one with POST /api/session.
   * @returns {Promise<Me>}
   */
  async open () {
    const stored = this._read()
    if (stored) {
      try {
        const me = await apiRequest('GET', '/api/me', { token: stored.token })
        this.token = stored.token
        this.playerId = me.playerId
        return me
      } catch (error) {
        if (!(error instanceof ApiError) || error.status !== 401) throw error
      }
    }
    return this.renew()
  }

  /** A new guest session, stored. @returns {Promise<Me>} */
  async renew () {
    const created = await apiRequest('POST', '/api/session')
    this.token = created.token
    this.playerId = created.playerId
    this.storage.setItem(SESSION_KEY, JSON.stringify({ token: created.token, playerId: created.playerId }))
    return created
  }

  /** An authenticated API call. @param {string} method @param {string} path @param {any} [body] */
  request (method, path, body) {
    return apiRequest(method, path, { token: this.token, body })
  }

  _read () {
    try {
      const value = JSON.parse(this.storage.getItem(SESSION_KEY) ?? 'null')
      return value && typeof value.token === 'string' ? value : null
    } catch {
      return null
    }
  }
}
