import { TokenBucket } from '../limits/token-bucket.js'
import { soleWorker } from '../limits/worker-share.js'

/**
 * Once its address's frame budget is spent, a socket still gets frames
 * through while it has gone at most this many frames past its own rate
 * (and sends frames of at most QUIET_FRAME_BYTES): an honest player behind
 * the same address as a flooder keeps playing, every flooder is cut off.
 */
export const QUIET_SLACK = 10
export const QUIET_FRAME_BYTES = 1024

/**
 * What one client IP may do over WebSockets, across all its connections
 * and sessions: how many sockets it holds open, token buckets for its
 * drops and joins (a player who opens many sessions from one address still
 * shares these), and a budget of frames and bytes received over all its
 * sockets (WS_IP_MESSAGE_RATE, WS_IP_BYTE_RATE, each bucket two seconds'
 * worth): the per-socket burst (WS_MESSAGE_BURST) no longer adds up across
 * sockets. An entry lives while the IP has sockets open, and then until its
 * buckets have refilled, so closing and reopening a socket never hands out
 * a fresh burst. In a cluster each process enforces 1/N of every budget,
 * N the processes alive (limits/worker-share.js), so that the cluster's
 * limit is the configured one.
 */
export class IpLimits {
  /**
   * @param {{ dropRate: number, joinRate: number, messageRate?: number, byteRate?: number, maxPayload?: number, maxSockets?: number,
   *   share?: import('../limits/worker-share.js').WorkerShare, now?: () => number }} options
   *   rates per second (messages: frames received, bytes: their payloads); each bucket holds two seconds' worth
   *   (the byte bucket at least one frame of maxPayload); all of them the whole cluster's, divided by share.workers
   */
  constructor ({ dropRate, joinRate, messageRate = Infinity, byteRate = Infinity, maxPayload = 0, maxSockets = Infinity, share = soleWorker(), now }) {
    this.configured = { dropRate, joinRate, messageRate, byteRate, maxSockets }
    this.maxPayload = maxPayload
    this.now = now
    /** @type {Map<string, IpEntry>} */
    this.entries = new Map()
    this._divide(share.workers)
    share.onChange((workers) => {
      this._divide(workers)
      for (const entry of this.entries.values()) this._resize(entry)
    })
  }

  /** This process's share of each budget: 1/workers, at least one socket. @param {number} workers */
  _divide (workers) {
    const { dropRate, joinRate, messageRate, byteRate, maxSockets } = this.configured
    this.dropRate = dropRate / workers
    this.joinRate = joinRate / workers
    this.messageRate = messageRate / workers
    this.byteRate = byteRate / workers
    this.maxSockets = Math.max(1, Math.floor(maxSockets / workers))
  }

  /**
   * Rate and burst of each of an address's buckets, from this process's share:
   * two seconds' worth, the byte bucket at least one frame of maxPayload.
   */
  _bucketSizes () {
    return {
      drops: [this.dropRate, 2 * this.dropRate],
      joins: [this.joinRate, 2 * this.joinRate],
      frames: [this.messageRate, 2 * this.messageRate],
      bytes: [this.byteRate, Math.max(2 * this.byteRate, this.maxPayload)]
    }
  }

  /** @param {IpEntry} entry */
  _resize (entry) {
    for (const [name, [rate, burst]] of Object.entries(this._bucketSizes())) entry[name].resize(rate, burst)
  }

  /** Open sockets from `ip` now. @param {string} ip */
  openFrom (ip) {
    return this.entries.get(ip)?.open ?? 0
  }

  /** Whether `ip` holds this process's share of sockets already. @param {string} ip */
  atSocketLimit (ip) {
    return this.openFrom(ip) >= this.maxSockets
  }

  /**
   * Counts a new socket from `ip`; returns its entry (release it on close).
   * @param {string} ip
   */
  acquire (ip) {
    let entry = this.entries.get(ip)
    if (!entry) {
      const buckets = {}
      for (const [name, [rate, burst]] of Object.entries(this._bucketSizes())) buckets[name] = new TokenBucket({ rate, burst, now: this.now })
      entry = new IpEntry(ip, buckets)
      this.entries.set(ip, entry)
    }
    entry.open++
    return entry
  }

  /** @param {IpEntry} entry */
  release (entry) {
    entry.open--
  }

  /** Forgets IPs with no socket open whose buckets are full again. Returns how many it forgot. */
  sweep () {
    let forgotten = 0
    for (const [ip, entry] of this.entries) {
      if (entry.open === 0 && entry.drops.isFull() && entry.joins.isFull() && entry.frames.isFull() && entry.bytes.isFull()) {
        this.entries.delete(ip)
        forgotten++
      }
    }
    return forgotten
  }
}

/**
 * An address entry that lifts nothing (every drop, join and frame is let
 * through): what a connection holds until the route has counted it against
 * its address (one refused at capacity never is), and what the benchmark's
 * in-process players hold, having no address.
 */
export const NO_ADDRESS_LIMITS = Object.freeze({
  drops: Object.freeze({ take: () => true }),
  joins: Object.freeze({ take: () => true }),
  admitFrame: () => true
})

class IpEntry {
  /** @param {string} ip @param {{ drops: TokenBucket, joins: TokenBucket, frames: TokenBucket, bytes: TokenBucket }} buckets */
  constructor (ip, { drops, joins, frames, bytes }) {
    this.ip = ip
    this.open = 0
    this.drops = drops
    this.joins = joins
    this.frames = frames
    this.bytes = bytes
  }

  /**
   * Takes a received frame of `size` bytes from the address's budget. Past
   * it, only a quiet socket's frame is let through (small, and its own
   * bucket within QUIET_SLACK of full); the caller closes the socket
   * otherwise. @param {number} size
   * @param {{ tokens: number, burst: number }} socketLimiter the socket's own frame bucket, already taken from
   * @returns {boolean}
   */
  admitFrame (size, socketLimiter) {
    const frames = this.frames.take()
    const bytes = this.bytes.take(size)
    if (frames && bytes) return true
    return size <= QUIET_FRAME_BYTES && socketLimiter.tokens >= socketLimiter.burst - 1 - QUIET_SLACK
  }
}
