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
 * The player holds no socket: `send` writes a text message, and the owner
 * (lean-worker.js) feeds it what arrives, so the checks are tested alone.
 */

import { ownerSocketUrl } from '../k6-lib/scenario-config.js'

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

export class LeanPlayer {
  /**
   * @param {object} options
   * @param {string} options.room the room to join
   * @param {number} options.bet credits per drop
   * @param {PlayerStats} options.stats where the player's counts go
   * @param {(text: string) => void} options.send writes one text message to the server
   * @param {(socketUrl: string) => void} [options.redirect] reconnect to this ws:// URL (the room's process) and play on there
   * @param {() => number} [options.now] ms, the same clock as the arrival times given to receive*()
   */
  constructor ({ room, bet, stats, send, redirect, now = () => performance.now() }) {
    this.room = room
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
    switch (message.type) {
      case 'welcome':
        this.playerId = message.playerId
        this.balance = milli(message.balance)
        // A new connection (after a redirect: another process, its own ticks).
        this.lastTick = -1
        this.send(JSON.stringify({ type: 'join', room: this.room }))
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

  /** A binary frame: counted, and its snapshot tick checked. @param {Uint8Array} buffer @param {number} start @param {number} end */
  receiveBinary (buffer, start, end) {
    const stats = this.stats
    stats.frames++
    stats.bytes += end - start
    const tick = frameTick(buffer, start, end)
    if (tick < 0) return stats.error('X_BAD_FRAME', `binary frame of kind ${buffer[start]}, ${end - start} bytes`)
    if (tick <= this.lastTick) stats.error('X_TICK_ORDER', `snapshot tick ${tick} after ${this.lastTick}`)
    this.lastTick = tick
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
