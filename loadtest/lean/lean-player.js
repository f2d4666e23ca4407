/**
 * One simulated player of the lean load generator and its checks, as strict
 * as the k6 player's (loadtest/k6-lib/player.js):
 *
 * - every own `dropped` and `settled` carries the running balance: previous
 *   − bet (dropped) or + payout (settled), from `welcome.balance`, compared
 *   in milli-credits (credits have up to three decimals);
 * - payout = bet × multiplier exactly (milli-credits);
 * - every drop sent is acknowledged (`dropped`, matched by `ref`) or refused
 *   (an error with its `ref`, counted as an error), and every announced drop
 *   is settled before the player leaves (`unsettled` counts the others);
 * - every error frame, unexpected close, failed request or malformed frame
 *   is counted by code, and so is a player that had to leave before its
 *   `joined` came (X_NOT_JOINED); the room's snapshot ticks must increase frame by
 *   frame (X_TICK_ORDER).
 *
 * - clustered, a join answered E_WRONG_NODE (before any `joined`) is
 *   followed, as the k6 player does: `redirect(socketUrl)` asks the owner
 *   to reconnect to the room's process (loopback only) with the same
 *   session, at most MAX_REDIRECTS times; a redirect is counted, not an
 *   error.
 *
 * It decodes only what it checks: text frames (the player's own events,
 * `welcome`, `joined`, errors) are parsed as JSON; a binary room frame is
 * counted, and its snapshot tick read from the header (kind 2: uint32 LE
 * events length L at offset 1, the snapshot at 5 + L, its tick at 6 + L;
 * kind 1: the tick at offset 1; see protocol/snapshot-codec.js). The other
 * players' events in it are never parsed.
 *
 * In seeds mode (`delivery: "seeds"`, the page's mode) a snapshot or room
 * frame is an error (X_UNEXPECTED_SNAPSHOT); drop-events frames (kind 3)
 * are checked as the page's decoder checks them and read for their drop ids
 * and players (scanDropEvents in protocol/drop-events-codec.js; X_BAD_FRAME
 * where decodeDropEvents would fail), their ticks must
 * increase (X_TICK_ORDER), and each other player's drop in them is timed
 * from the moment its owner sent it to its arrival here, when the owner is
 * a player of the same worker (DropSightings: the two share a clock).
 *
 * The player holds no socket: `send` writes a text message, and the owner
 * (lean-worker.js) feeds it what arrives, so the checks are tested alone.
 */

import { ownerSocketUrl } from '../k6-lib/scenario-config.js'
import { scanDropEvents, DROP_EVENTS_KIND } from '../../protocol/drop-events-codec.js'

const TICK_MS = 1000 / 60
/** E_WRONG_NODE answers followed before joining; one more is an error (two processes disagreeing). */
export const MAX_REDIRECTS = 3
const SNAPSHOT_KIND = 1
const ROOM_FRAME_KIND = 2

/** A growable array of doubles (latencies, ms). */
export class Samples {
  constructor (capacity = 1024) {
    this.values = new Float64Array(capacity)
    this.length = 0
  }

  /** @param {number} value */
  add (value) {
    if (this.length === this.values.length) {
      const grown = new Float64Array(this.values.length * 2)
      grown.set(this.values)
      this.values = grown
    }
    this.values[this.length++] = value
  }

  /** @returns {Float64Array} a copy of the values added */
  toArray () {
    return this.values.slice(0, this.length)
  }
}

/** What all the players of one worker add up to. */
export class PlayerStats {
  constructor () {
    this.players = 0
    this.joined = 0
    /** Joins answered E_WRONG_NODE and followed to the room's process. */
    this.redirects = 0
    this.finished = 0
    this.dropsSent = 0
    this.dropsAcked = 0
    this.dropsRefused = 0
    this.dropsSettled = 0
    this.unsettled = 0
    this.balanceMismatches = 0
    /** Binary frames and text messages received, and their payload bytes. */
    this.frames = 0
    this.textMessages = 0
    this.bytes = 0
    /** @type {Map<string, number>} error code → count */
    this.errors = new Map()
    /** drop sent → own `dropped`, ms */
    this.ackMs = new Samples()
    /** drop sent → own `settled`, ms (includes the ball's fall) */
    this.settledMs = new Samples()
    /** drop sent → own `settled` minus the fall ((ticks − 1) / 60 s), ms */
    this.settleOverheadMs = new Samples()
    /**
     * The steady window (the owner's clock, as `now`): drops sent within it
     * are also timed in the steady* samples, without the ramp's connects.
     */
    this.steadyFrom = Infinity
    this.steadyTo = Infinity
    this.steadyAckMs = new Samples()
    this.steadySettledMs = new Samples()
    /** Seeds mode: another player's drop, sent by its owner → seen in a drop-events frame here, ms (drops sent in the steady window) */
    this.steadySightingMs = new Samples()
    /**
     * The same sightings' room ticks from the ball's release (its start tick)
     * to the tick of the frame that carried it: the room's 1/EVENT_HZ
     * batching and any hold for a commit, apart from the rest of the way.
     */
    this.steadySightingTicks = new Samples()
    /** Seeds mode: drop-events frames and the other players' drops in them (own drops and repeats excluded). */
    this.eventFrames = 0
    this.eventsSeen = 0
    /** The first few errors in words, for the report. */
    this.firstErrors = []
  }

  /** @param {string} code @param {string} [detail] */
  error (code, detail) {
    this.errors.set(code, (this.errors.get(code) ?? 0) + 1)
    if (detail !== undefined && this.firstErrors.length < 10) this.firstErrors.push(`${code}: ${detail}`)
  }

  get errorCount () {
    let total = 0
    for (const count of this.errors.values()) total += count
    return total
  }
}

/** Credits (up to three decimals, as the server sends them) in milli-credits, for exact sums. @param {number} credits */
export function milli (credits) {
  return Math.round(credits * 1000)
}

/**
 * The snapshot tick of a binary frame (room frame or bare snapshot), or -1
 * when the frame is of another kind or too short to hold one.
 * @param {Uint8Array} buffer @param {number} start @param {number} end
 */
export function frameTick (buffer, start, end) {
  let at = start
  const kind = buffer[at]
  if (kind === ROOM_FRAME_KIND) {
    if (end - start < 5) return -1
    const length = (buffer[at + 1] | (buffer[at + 2] << 8) | (buffer[at + 3] << 16)) + buffer[at + 4] * 16777216
    at += 5 + length
    if (at >= end || buffer[at] !== SNAPSHOT_KIND) return -1
  } else if (kind !== SNAPSHOT_KIND) {
    return -1
  }
  if (end - at < 7) return -1
  return (buffer[at + 1] | (buffer[at + 2] << 8) | (buffer[at + 3] << 16)) + buffer[at + 4] * 16777216
}

/**
 * When the drops of one worker's players were sent, so that the worker's
 * other players can time their arrival in drop-events frames on the same
 * clock. A drop is timed only when its owner is a player of this worker; an
 * event that comes before its owner's `dropped` waits for it.
 */
export class DropSightings {
  /** @param {PlayerStats} stats */
  constructor (stats) {
    this.stats = stats
    /** @type {Set<string>} */
    this.players = new Set()
    /** dropId → sent at (ms) @type {Map<number, number>} */
    this.sentAt = new Map()
    /** dropId → (arrival time, ticks after release) pairs seen before the owner's `dropped` @type {Map<number, number[]>} */
    this.early = new Map()
  }

  /** @param {string} playerId a player of this worker */
  player (playerId) { this.players.add(playerId) }

  /** The owner's `dropped` came. @param {number} dropId @param {number} sentAt */
  sent (dropId, sentAt) {
    this.sentAt.set(dropId, sentAt)
    const early = this.early.get(dropId)
    if (!early) return
    this.early.delete(dropId)
    for (let i = 0; i < early.length; i += 2) this._record(sentAt, early[i], early[i + 1])
  }

  /** The owner's `settled` came: every frame naming the drop has long gone out. @param {number} dropId */
  settled (dropId) { this.sentAt.delete(dropId) }

  /**
   * Another player's drop arrived at `at`, in a frame `ticks` room ticks
   * after its release.
   * @param {number} dropId @param {string} owner @param {number} at @param {number} ticks
   */
  seen (dropId, owner, at, ticks) {
    if (!this.players.has(owner)) return
    const sentAt = this.sentAt.get(dropId)
    if (sentAt !== undefined) return this._record(sentAt, at, ticks)
    const early = this.early.get(dropId)
    if (early) early.push(at, ticks)
    else this.early.set(dropId, [at, ticks])
  }

  _record (sentAt, at, ticks) {
    const stats = this.stats
    if (sentAt < stats.steadyFrom || sentAt >= stats.steadyTo) return
    stats.steadySightingMs.add(at - sentAt)
    stats.steadySightingTicks.add(ticks)
  }
}

export class LeanPlayer {
  /**
   * @param {object} options
   * @param {string} options.room the room to join
   * @param {number} options.bet credits per drop
   * @param {PlayerStats} options.stats where the player's counts go
   * @param {(text: string) => void} options.send writes one text message to the server
   * @param {(socketUrl: string) => void} [options.redirect] reconnect to this ws:// URL (the room's process) and play on there
   * @param {() => number} [options.now] ms, the same clock as the arrival times given to receive*()
   * @param {'snapshots' | 'seeds'} [options.delivery] the `join.delivery` to ask for
   * @param {DropSightings} [options.sightings] the worker's, to time the other players' drops (seeds mode)
   */
  constructor ({ room, bet, stats, send, redirect, now = () => performance.now(), delivery = 'snapshots', sightings = new DropSightings(stats) }) {
    this.room = room
    this.delivery = delivery
    this.sightings = sightings
    this.bet = bet
    this.stats = stats
    this.send = send
    this.redirect = redirect
    this.redirects = 0
    this.now = now
    this.playerId = null
    /** Running balance, milli-credits. */
    this.balance = 0
    this.joined = false
    this.leaving = false
    this.finished = false
    this.seq = 0
    this.lastTick = -1
    /** ref → sent at: sent, not yet acknowledged or refused. @type {Map<number, number>} */
    this.pending = new Map()
    /** dropId → sent at: announced, not yet settled. @type {Map<string, number>} */
    this.inFlight = new Map()
    /** Arrival time of the drop-events frame being read (_dropEvents). */
    this.frameAt = 0
    /** One event of a drop-events frame: another player's drop, timed (scanDropEvents' callback, made once). */
    this.otherDrop = (dropId, player, startTick, tick) => {
      if (player === this.playerId) return
      this.stats.eventsSeen++
      this.sightings.seen(dropId, player, this.frameAt, tick - startTick)
    }
    stats.players++
  }

  /** Nothing left to wait for: every drop sent is acknowledged (or refused) and settled. */
  get drained () {
    return this.pending.size === 0 && this.inFlight.size === 0
  }

  /** @param {string} text @param {number} at arrival time */
  receiveText (text, at) {
    const stats = this.stats
    stats.textMessages++
    stats.bytes += text.length
    let message
    try {
      message = JSON.parse(text)
    } catch {
      return stats.error('X_BAD_JSON', text.slice(0, 80))
    }
    this.receiveMessage(message, at)
  }

  /** A server message, from a text frame or a drop-events frame's owner's section. @param {any} message @param {number} at */
  receiveMessage (message, at) {
    const stats = this.stats
    switch (message.type) {
      case 'welcome':
        this.playerId = message.playerId
        this.balance = milli(message.balance)
        // A new connection (after a redirect: another process, its own ticks).
        this.lastTick = -1
        this.sightings.player(message.playerId)
        this.send(JSON.stringify(this.delivery === 'seeds' ? { type: 'join', room: this.room, delivery: 'seeds' } : { type: 'join', room: this.room }))
        return
      case 'joined':
        if (!this.joined) {
          this.joined = true
          stats.joined++
        }
        return
      case 'dropped':
        if (message.player === this.playerId) this._dropped(message, at)
        return
      case 'settled':
        if (message.player === this.playerId) this._settled(message, at)
        return
      case 'error':
        if (message.code === 'E_WRONG_NODE' && this._follow(message.owner)) return
        stats.error(message.code, message.message)
        if (message.ref !== undefined && this.pending.delete(message.ref)) stats.dropsRefused++
    }
  }

  /**
   * Follows an E_WRONG_NODE to the room's owner, when the player can:
   * before its `joined`, with nothing sent but the join, the owner on
   * loopback, and redirects left. @param {unknown} owner @returns {boolean} followed
   */
  _follow (owner) {
    const url = ownerSocketUrl(owner)
    if (!this.redirect || this.joined || url === null || this.redirects >= MAX_REDIRECTS || this.pending.size > 0) return false
    this.redirects++
    this.stats.redirects++
    this.redirect(url)
    return true
  }

  /** A binary frame: counted, and its snapshot tick checked. @param {Uint8Array} buffer @param {number} start @param {number} end @param {number} [at] arrival time */
  receiveBinary (buffer, start, end, at = this.now()) {
    const stats = this.stats
    stats.frames++
    stats.bytes += end - start
    if (this.delivery === 'seeds') return this._dropEvents(buffer, start, end, at)
    const tick = frameTick(buffer, start, end)
    if (tick < 0) return stats.error('X_BAD_FRAME', `binary frame of kind ${buffer[start]}, ${end - start} bytes`)
    if (tick <= this.lastTick) stats.error('X_TICK_ORDER', `snapshot tick ${tick} after ${this.lastTick}`)
    this.lastTick = tick
  }

  /**
   * Seeds mode: a drop-events frame, checked as the page's decoder checks it,
   * the other players' drops in it timed. Read for its drop ids and players
   * only (scanDropEvents): decoding every event whole, its seed as text,
   * cost the generator some 3 µs of its 19–25 per frame at 6,000 players,
   * and a busy generator's own lag is in every latency it measures
   * (loadtest/RESULTS.md).
   */
  _dropEvents (buffer, start, end, at) {
    const stats = this.stats
    if (buffer[start] !== DROP_EVENTS_KIND) return stats.error('X_UNEXPECTED_SNAPSHOT', `binary frame of kind ${buffer[start]} on a seeds socket`)
    this.frameAt = at
    const frame = scanDropEvents(buffer.subarray(start, end), this.otherDrop)
    if (frame === null) return stats.error('X_BAD_FRAME', `drop-events frame of ${end - start} bytes does not decode`)
    if (frame.tick <= this.lastTick) stats.error('X_TICK_ORDER', `drop-events tick ${frame.tick} after ${this.lastTick}`)
    this.lastTick = frame.tick
    stats.eventFrames++
    // The owner's section: this player's own `settled`, as if each had come on its own.
    for (const message of frame.own) this.receiveMessage(message, at)
  }

  /** Sends one drop (none before `joined` or once leaving). @returns {boolean} sent */
  drop () {
    if (!this.joined || this.leaving) return false
    const ref = ++this.seq
    this.pending.set(ref, this.now())
    this.send(`{"type":"drop","bet":${this.bet},"ref":${ref}}`)
    this.stats.dropsSent++
    return true
  }

  /** Stops dropping (the owner then waits for `drained`, or its deadline). */
  leave () {
    this.leaving = true
  }

  /**
   * The socket closed: anything still pending or in flight is unsettled.
   * @param {number} code @param {boolean} byUs the player asked to close
   */
  closed (code, byUs) {
    if (this.finished) return
    this.finished = true
    this.leaving = true
    const stats = this.stats
    stats.finished++
    if (!byUs) stats.error(`WS_CLOSE_${code}`, `player ${this.playerId}: server closed the connection`)
    // A player that leaves (its time is up) still waiting for `joined` never played: as much an error as a timeout.
    else if (!this.joined) stats.error('X_NOT_JOINED', `player ${this.playerId}: no joined before leaving`)
    const unsettled = this.pending.size + this.inFlight.size
    if (unsettled > 0) stats.unsettled += unsettled
  }

  _dropped (message, at) {
    const stats = this.stats
    const sentAt = this.pending.get(message.ref)
    if (sentAt === undefined) {
      stats.error('X_UNKNOWN_DROP', `dropped ${message.dropId} with ref ${message.ref} that this player did not send`)
    } else {
      this.pending.delete(message.ref)
      stats.dropsAcked++
      stats.ackMs.add(at - sentAt)
      if (sentAt >= stats.steadyFrom && sentAt < stats.steadyTo) stats.steadyAckMs.add(at - sentAt)
      this.inFlight.set(message.dropId, sentAt)
      this.sightings.sent(message.dropId, sentAt)
    }
    this._checkBalance(message, this.balance - message.bet * 1000)
  }

  _settled (message, at) {
    const stats = this.stats
    const sentAt = this.inFlight.get(message.dropId)
    if (sentAt === undefined) {
      stats.error('X_UNKNOWN_SETTLE', `settled ${message.dropId} that was never announced to this player`)
    } else {
      this.inFlight.delete(message.dropId)
      this.sightings.settled(message.dropId)
      stats.dropsSettled++
      const latency = at - sentAt
      stats.settledMs.add(latency)
      if (sentAt >= stats.steadyFrom && sentAt < stats.steadyTo) stats.steadySettledMs.add(latency)
      // The ball takes its first step on the tick after the drop arrived.
      stats.settleOverheadMs.add(latency - (message.ticks - 1) * TICK_MS)
    }
    const payout = message.bet * Math.round(message.multiplier * 1000)
    if (milli(message.payout) !== payout) stats.error('X_BAD_PAYOUT', `drop ${message.dropId}: payout ${message.payout}, expected ${payout / 1000}`)
    this._checkBalance(message, this.balance + milli(message.payout))
  }

  /** @param {{ type: string, dropId: string, balance: number }} message @param {number} expected milli-credits */
  _checkBalance (message, expected) {
    const balance = milli(message.balance)
    if (balance !== expected) {
      this.stats.balanceMismatches++
      this.stats.error('X_BALANCE_MISMATCH', `${message.type} ${message.dropId}: balance ${message.balance}, expected ${expected / 1000}`)
    }
    this.balance = balance
  }
}
