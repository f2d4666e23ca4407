import fs from 'node:fs'
import { STATUS_CODES } from 'node:http'
import { ERROR_CODES } from '../errors.js'

/** Descriptors kept back from HTTP connections: the ledger, Redis, logs, the WAL, DNS. */
const RESERVED_DESCRIPTORS = 0.1

/**
 * The process's soft limit on open files (Linux: /proc/self/limits), or
 * null where it cannot be read.
 */
export function openFileLimit () {
  try {
    const line = fs.readFileSync('/proc/self/limits', 'utf8').split('\n').find((l) => l.startsWith('Max open files'))
    const soft = Number(line?.split(/\s{2,}/)[1])
    return Number.isSafeInteger(soft) && soft > 0 ? soft : null
  } catch {
    return null
  }
}

/**
 * How many HTTP connections (WebSockets included: they start as one) the
 * process holds at most: HTTP_MAX_CONNECTIONS, but never more than 90% of
 * the open-file limit, so accept() never fails with EMFILE and the ledger
 * can always open a file. 0 = that ceiling.
 * @param {number} configured @param {number | null} [fileLimit]
 */
export function connectionCeiling (configured, fileLimit = openFileLimit()) {
  const ceiling = fileLimit === null ? Infinity : Math.max(16, Math.floor(fileLimit * (1 - RESERVED_DESCRIPTORS)))
  const wanted = configured === 0 ? Infinity : configured
  const max = Math.min(wanted, ceiling)
  return Number.isFinite(max) ? max : 16_384
}

/**
 * Caps the HTTP server's TCP connections in total and per peer address
 * (issue #21: 22,000 slowloris connections took a server to its descriptor
 * limit, and honest probes failed for 30 s). At a cap, a new connection
 * makes room by closing the connection that has been idle longest (no
 * request in progress: a slow sender still writing its headers, a
 * keep-alive between requests, one that never sent anything) — of its
 * address when that address is at its cap, else of the whole server; if
 * none is idle, the new one is refused with 429 E_TOO_MANY_CONNECTIONS.
 * Upgraded WebSockets count but are never shed here (their own limits
 * apply, WS_MAX_CONNECTIONS*).
 *
 * The per-address cap counts the TCP peer: behind a proxy (TRUST_PROXY)
 * that is the proxy, so it is then off and only the total applies.
 */
export class ConnectionLimits {
  /**
   * @param {{ maxTotal: number, maxPerAddress: number | null, metrics: import('../metrics.js').Metrics }} options
   */
  constructor ({ maxTotal, maxPerAddress, metrics }) {
    this.maxTotal = maxTotal
    this.maxPerAddress = maxPerAddress
    this.metrics = metrics
    this.open = 0
    /** Idle sockets, longest idle first (a Set keeps insertion order). @type {Set<import('node:net').Socket>} */
    this.idle = new Set()
    /** Per address: how many are open and which are idle, longest first. @type {Map<string, { open: number, idle: Set<import('node:net').Socket> }>} */
    this.addresses = new Map()
  }

  /** @param {import('node:http').Server} server */
  attach (server) {
    server.on('connection', (socket) => this._connected(socket))
    server.on('request', (request, response) => {
      this._busy(request.socket)
      response.once('close', () => this._idle(request.socket))
    })
    server.on('upgrade', (request) => {
      request.socket.plinkoUpgraded = true
      this._busy(request.socket)
    })
  }

  _connected (socket) {
    const address = socket.remoteAddress ?? 'unknown'
    let entry = this.addresses.get(address)
    if (this.maxPerAddress !== null && entry && entry.open >= this.maxPerAddress) {
      if (!this._shedOldest(entry.idle, 'per_address')) return this._refuse(socket, 'per_address')
    }
    if (this.open >= this.maxTotal && !this._shedOldest(this.idle, 'total')) return this._refuse(socket, 'total')
    if (!entry) this.addresses.set(address, (entry = { open: 0, idle: new Set() }))
    entry.open++
    this.open++
    this.metrics.httpConnections.set(this.open)
    socket.plinkoAddress = entry
    this._idle(socket)
    socket.once('close', () => {
      this.idle.delete(socket)
      entry.idle.delete(socket)
      entry.open--
      this.open--
      this.metrics.httpConnections.set(this.open)
      if (entry.open === 0) this.addresses.delete(address)
    })
  }

  _idle (socket) {
    const entry = socket.plinkoAddress
    if (!entry || socket.destroyed || socket.plinkoUpgraded) return
    this.idle.delete(socket)
    entry.idle.delete(socket)
    this.idle.add(socket)
    entry.idle.add(socket)
  }

  _busy (socket) {
    this.idle.delete(socket)
    socket.plinkoAddress?.idle.delete(socket)
  }

  /** Closes the longest-idle socket of `idle`; false if there is none. */
  _shedOldest (idle, reason) {
    const oldest = idle.values().next().value
    if (!oldest) return false
    this.idle.delete(oldest)
    oldest.plinkoAddress?.idle.delete(oldest)
    oldest.destroy()
    this.metrics.httpConnectionsShed.labels(reason).inc()
    return true
  }

  _refuse (socket, reason) {
    this.metrics.httpConnectionsRefused.labels(reason).inc()
    const body = JSON.stringify({ code: 'E_TOO_MANY_CONNECTIONS', message: reason === 'total' ? 'too many connections to this server; try again shortly' : 'too many connections from this address; close one or try again shortly' })
    const status = ERROR_CODES.E_TOO_MANY_CONNECTIONS.status
    socket.on('error', () => {})
    socket.end(`HTTP/1.1 ${status} ${STATUS_CODES[status]}\r\nContent-Type: application/json; charset=utf-8\r\nContent-Length: ${Buffer.byteLength(body)}\r\nRetry-After: 1\r\nConnection: close\r\n\r\n${body}`)
    socket.destroySoon?.()
    setTimeout(() => socket.destroy(), 1000).unref()
  }
}
