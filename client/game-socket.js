/**
 * The game's WebSocket, kept up by itself: after any drop of the connection
 * it reconnects with exponential backoff (250 ms doubling to 8 s, with
 * jitter) and the caller re-joins its room on the next `welcome`. A ping
 * every few seconds measures the round trip and detects a silent peer.
 */

const BACKOFF_FIRST_MS = 250
const BACKOFF_MAX_MS = 8000
const PING_EVERY_MS = 5000
/** Without any message for this long the connection is considered dead and replaced. */
const SILENCE_LIMIT_MS = 15000
/** The server's close code for a refused session token. */
export const CLOSE_UNAUTHORIZED = 4401

/**
 * @typedef {'connecting' | 'open' | 'waiting' | 'stopped'} SocketStatus
 */

export class GameSocket {
  /**
   * @param {object} handlers
   * @param {() => string} handlers.url the URL to connect to (asked at each attempt: the token may change)
   * @param {(message: any) => void} handlers.onMessage JSON messages
   * @param {(frame: ArrayBuffer, receivedAt: number) => void} handlers.onBinary binary frames (snapshots)
   * @param {(status: SocketStatus, detail: { attempt: number, retryInMs?: number, code?: number }) => void} handlers.onStatus
   * @param {(code: number, reason: string) => boolean | void} [handlers.onClose] return false to stop reconnecting
   */
  constructor ({ url, onMessage, onBinary, onStatus, onClose }) {
    this.url = url
    this.onMessage = onMessage
    this.onBinary = onBinary
    this.onStatus = onStatus
    this.onClose = onClose ?? (() => {})
    /** @type {WebSocket | null} */
    this.socket = null
    this.attempt = 0
    this.connects = 0
    this.stopped = true
    this.rttMs = null
    this._retryTimer = null
    this._pingTimer = null
    this._lastMessageAt = 0
    this._pingSentAt = 0
    this._pingRef = 0
  }

  start () {
    this.stopped = false
    this._connect()
  }

  stop () {
    this.stopped = true
    clearTimeout(this._retryTimer)
    clearInterval(this._pingTimer)
    this.socket?.close(1000, 'bye')
    this.socket = null
    this.onStatus('stopped', { attempt: this.attempt })
  }

  get isOpen () {
    return this.socket?.readyState === WebSocket.OPEN
  }

  /** Sends a JSON message; false when not connected (nothing is queued). @param {object} message */
  send (message) {
    if (!this.isOpen) return false
    this.socket.send(JSON.stringify(message))
    return true
  }

  /**
   * Replaces the connection at once, without backoff: the URL changed
   * (E_WRONG_NODE named another process).
   */
  reconnectNow () {
    const socket = this.socket
    this.socket = null
    clearInterval(this._pingTimer)
    clearTimeout(this._retryTimer)
    socket?.close(1000, 'moving to another server')
    if (this.stopped) return
    this.attempt = 0
    this._connect()
  }

  /** Closes the current connection as if the network dropped it (used by tests and the UI). */
  drop () {
    this._abandon(4000, 'closed by the client')
  }

  _connect () {
    if (this.stopped) return
    this.onStatus('connecting', { attempt: this.attempt })
    const socket = new WebSocket(this.url())
    socket.binaryType = 'arraybuffer'
    this.socket = socket
    socket.addEventListener('open', () => {
      if (socket !== this.socket) return
      this.connects++
      this._lastMessageAt = performance.now()
      clearInterval(this._pingTimer)
      this._pingTimer = setInterval(() => this._heartbeat(), PING_EVERY_MS)
      this.onStatus('open', { attempt: this.attempt })
    })
    socket.addEventListener('message', (event) => {
      if (socket !== this.socket) return
      const now = performance.now()
      this._lastMessageAt = now
      if (typeof event.data !== 'string') {
        this.onBinary(event.data, now)
        return
      }
      let message
      try {
        message = JSON.parse(event.data)
      } catch {
        return
      }
      if (message.type === 'welcome') this.attempt = 0
      if (message.type === 'pong' && message.ref === `hb-${this._pingRef}`) this.rttMs = now - this._pingSentAt
      this.onMessage(message)
    })
    // 'error' is always followed by 'close', which does the work.
    socket.addEventListener('close', (event) => this._lost(socket, event.code, event.reason))
  }

  /**
   * The connection `socket` is gone (closed by either side, or given up on):
   * schedule the next attempt unless stopped. Runs once per socket.
   * @param {WebSocket} socket @param {number} code @param {string} reason
   */
  _lost (socket, code, reason) {
    if (socket !== this.socket) return
    clearInterval(this._pingTimer)
    this.socket = null
    if (this.stopped) return
    if (this.onClose(code, reason) === false) {
      this.stopped = true
      this.onStatus('stopped', { attempt: this.attempt, code })
      return
    }
    const retryInMs = this._backoff()
    this.onStatus('waiting', { attempt: this.attempt, retryInMs, code })
    this._retryTimer = setTimeout(() => this._connect(), retryInMs)
  }

  /** Closes `socket` and moves on at once, without waiting for the closing handshake. */
  _abandon (code, reason) {
    const socket = this.socket
    if (!socket) return
    socket.close(code, reason)
    this._lost(socket, code, reason)
  }

  _backoff () {
    const base = Math.min(BACKOFF_MAX_MS, BACKOFF_FIRST_MS * 2 ** this.attempt)
    this.attempt++
    return Math.round(base * (0.8 + 0.4 * Math.random()))
  }

  _heartbeat () {
    if (!this.isOpen) return
    if (performance.now() - this._lastMessageAt > SILENCE_LIMIT_MS) {
      this._abandon(4001, 'no message from the server')
      return
    }
    this._pingRef++
    this._pingSentAt = performance.now()
    this.send({ type: 'ping', ref: `hb-${this._pingRef}` })
  }
}
