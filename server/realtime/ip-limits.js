import { TokenBucket } from '../ledger/token-bucket.js'

/**
 * What one client IP may do over WebSockets, across all its connections
 * and sessions: how many sockets it holds open, and token buckets for its
 * drops and joins (a player who opens many sessions from one address still
 * shares these). An entry lives while the IP has sockets open, and then
 * until its buckets have refilled, so closing and reopening a socket never
 * hands out a fresh burst.
 */
export class IpLimits {
  /**
   * @param {{ dropRate: number, joinRate: number, now?: () => number }} options
   *   rates per second; each bucket holds two seconds' worth
   */
  constructor ({ dropRate, joinRate, now }) {
    this.dropRate = dropRate
    this.joinRate = joinRate
    this.now = now
    /** @type {Map<string, IpEntry>} */
    this.entries = new Map()
  }

  /** Open sockets from `ip` now. @param {string} ip */
  openFrom (ip) {
    return this.entries.get(ip)?.open ?? 0
  }

  /**
   * Counts a new socket from `ip`; returns its entry (release it on close).
   * @param {string} ip
   */
  acquire (ip) {
    let entry = this.entries.get(ip)
    if (!entry) {
      entry = new IpEntry(ip, {
        drops: new TokenBucket({ rate: this.dropRate, burst: 2 * this.dropRate, now: this.now }),
        joins: new TokenBucket({ rate: this.joinRate, burst: 2 * this.joinRate, now: this.now })
      })
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
      if (entry.open === 0 && entry.drops.isFull() && entry.joins.isFull()) {
        this.entries.delete(ip)
        forgotten++
      }
    }
    return forgotten
  }
}

class IpEntry {
  /** @param {string} ip @param {{ drops: TokenBucket, joins: TokenBucket }} buckets */
  constructor (ip, { drops, joins }) {
    this.ip = ip
    this.open = 0
    this.drops = drops
    this.joins = joins
  }
}
