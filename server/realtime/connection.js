import Ajv from 'ajv'
import { GameError, ERROR_CODES, gameError } from '../errors.js'
import { ENGINE_VERSION } from '../../engine/index.js'
import { toCredits } from '../game/money.js'
import { holdWritesUntilEndOfTurn } from './write-batcher.js'
import { OutgoingMessage, socketWriter } from './outgoing-message.js'
import { SIMULATION_HZ } from '../rooms/tick-scheduler.js'
import { welcomeMessage, leftMessage, pongMessage, errorMessage } from '../../protocol/server-messages.js'
import { clientMessageSchemas } from '../../protocol/client-messages.js'
import { discardUnread } from './discard-unread.js'
import { NO_ADDRESS_LIMITS } from './ip-limits.js'

/** Messages that may arrive while the token is being checked; more than this is abuse. */
const MAX_EARLY_MESSAGES = 32
/** A socket we drop for abuse gets this long to take our close frame before it is destroyed. */
export const DROP_GRACE_MS = 1000
/** Close code for a client over its frame rate (policy violation). */
const OVER_RATE_CLOSE = 1008

/**
 * One authenticated WebSocket: turns client frames into arena calls (each
 * parsed and checked against the client message schemas first:
 * createMessageParser, below) and sends events and snapshots back, minding
 * backpressure. Events (joined,
 * dropped, settled, errors, …) are always sent; snapshots are skipped while
 * the socket has more than `softLimit` bytes queued. A socket over
 * `hardLimit` is closed (1013, E_SLOW_CONSUMER): nothing is buffered
 * without bound. A client over its frame rate (WS_MESSAGE_RATE, protocol
 * pings included) gets one E_RATE_LIMITED and is closed with 1008. A socket
 * closed for abuse is not read any more and is destroyed DROP_GRACE_MS
 * later, so a flooder costs nothing once it is cut off.
 */
export class Connection {
  /**
   * @param {object} options
   * @param {import('ws').WebSocket} options.socket
   * @param {import('../arena.js').Arena} options.arena
   * @param {(text: string) => any} options.parseMessage createMessageParser's function, compiled once per server
   * @param {import('../metrics.js').Metrics} options.metrics
   * @param {import('pino').Logger} options.log
   * @param {number} options.softLimit @param {number} options.hardLimit bytes
   * @param {{ take: () => boolean, rate: number, tokens: number, burst: number }} options.messageLimiter frames per second allowed (a TokenBucket)
   */
  constructor ({ socket, arena, parseMessage, metrics, log, softLimit, hardLimit, messageLimiter }) {
    this.socket = socket
    /** Writes an OutgoingMessage to the socket (outgoing-message.js). */
    this._write = socketWriter(socket)
    this.arena = arena
    this.parseMessage = parseMessage
    this.metrics = metrics
    this.log = log
    this.softLimit = softLimit
    this.hardLimit = hardLimit
    this.messageLimiter = messageLimiter
    /** @type {import('../game/accounts.js').Account | null} */
    this.account = null
    /** @type {import('../rooms/room.js').Room | null} */
    this.room = null
    /** How this socket is fed in its room (its `join.delivery`, server/realtime/deliveries.js). @type {import('./deliveries.js').RoomFeed | null} */
    this.feed = null
    this.closed = false
    this.alive = true
    /** This client IP's shared drop, join and frame buckets (server/realtime/ip-limits.js), set by the route once it counts the socket. */
    this.ipLimits = NO_ADDRESS_LIMITS
    this._early = []
    /** JSON texts held for the room's next frame (RoomFeed.ownerSettled), oldest first. @type {string[]} */
    this._deferred = []
    socket.on('message', (data, isBinary) => {
      if (this.account) this._receive(data, isBinary)
      else if (this._early.push([data, isBinary]) > MAX_EARLY_MESSAGES) this.drop(1008, 'too many messages before authentication')
    })
    // Protocol-level pings count against the frame rate too: ws answers each with a pong.
    socket.on('ping', (data) => {
      if (!this.messageLimiter.take()) this._overRate()
      else if (!this.ipLimits.admitFrame(data.length, this.messageLimiter)) this._overRate('from this address')
    })
    socket.on('pong', () => { this.alive = true })
    socket.on('close', () => this._closed())
  }

  /**
   * Binds the connection to a player once the token has been checked
   * (null: refused). Queued early messages are then handled in order.
   * @param {import('../game/accounts.js').Account | null} account
   */
  authenticated (account) {
    if (!account) {
      this.sendError('E_UNAUTHORIZED', 'missing or invalid session token; create one with POST /api/session and connect to /ws?token=TOKEN')
      this.close(ERROR_CODES.E_UNAUTHORIZED.close, 'E_UNAUTHORIZED')
      return false
    }
    if (this.closed) return false
    this.account = account
    account.connections.add(this)
    this.arena.connected(this)
    this.sendJson(welcomeMessage({
      playerId: account.playerId,
      balance: toCredits(account.balance),
      serverSeedHash: account.seed.hash,
      clientSeed: account.clientSeed,
      nonce: account.seed.nextNonce,
      engineVersion: ENGINE_VERSION,
      tickRate: SIMULATION_HZ,
      minBet: this.arena.config.minBet,
      maxBet: this.arena.config.maxBet
    }))
    for (const [data, isBinary] of this._early.splice(0)) this._receive(data, isBinary)
    return true
  }

  _receive (data, isBinary) {
    if (this.closed) return
    if (!this.messageLimiter.take()) return this._overRate()
    // The budget shared by every socket of this address (ip-limits.js).
    if (!this.ipLimits.admitFrame(data.length, this.messageLimiter)) return this._overRate('from this address')
    let message
    try {
      if (isBinary) {
        this.metrics.messagesIn.labels('binary').inc()
        throw new GameError('E_BAD_MESSAGE', 'binary frames are not accepted; send JSON text frames')
      }
      message = this.parseMessage(data.toString('utf8'))
      this.metrics.messagesIn.labels(message.type).inc()
      this._handle(message)
    } catch (error) {
      if (!(error instanceof GameError)) {
        this.log.error({ err: error }, 'message handler failed')
        error = new GameError('E_INTERNAL')
      } else if (message === undefined && !isBinary) {
        this.metrics.messagesIn.labels('invalid').inc()
      }
      this.sendError(error.code, error.message, message?.ref ?? error.ref, error.details)
    }
  }

  /** Reports a failed async request (GameError or not). */
  _replyError (error, ref) {
    if (!(error instanceof GameError)) {
      this.log.error({ err: error }, 'message handler failed')
      error = new GameError('E_INTERNAL')
    }
    this.sendError(error.code, error.message, ref, error.details)
  }

  _handle (message) {
    const arena = this.arena
    switch (message.type) {
      case 'join': {
        if (!this.account.joinLimiter.take()) throw new GameError('E_RATE_LIMITED', `at most ${arena.config.joinRate} joins per second per player`)
        if (!this.ipLimits.joins.take()) throw new GameError('E_RATE_LIMITED', `at most ${arena.config.joinRatePerIp} joins per second from one address`)
        const joined = arena.join(this, message.room, message.delivery)
        // Joining a room this process does not run yet is async (the coordinator claims it).
        if (typeof joined?.then === 'function') {
          joined.then((reply) => this.sendJson(withRef(reply, message.ref)), (error) => this._replyError(error, message.ref))
        } else {
          this.sendJson(withRef(joined, message.ref))
        }
        break
      }
      case 'leave':
        this.sendJson(withRef(leftMessage(arena.leave(this)), message.ref))
        break
      case 'drop':
        arena.drop(this, message)
        break
      case 'ping':
        this.sendJson(withRef(pongMessage(Date.now(), this.room), message.ref))
        break
    }
  }

  // ---- sending ------------------------------------------------------------

  /** @param {object} message */
  sendJson (message) {
    this.sendEvent(JSON.stringify(message), message.type)
  }

  /**
   * An event the client must not miss: sent unless the socket is over the
   * hard limit, in which case the client is too slow and is closed.
   * @param {string} text @param {string} type for metrics
   */
  sendEvent (text, type) {
    if (this.closed) return
    if (this.socket.bufferedAmount > this.hardLimit) return this._tooSlow()
    // Held messages go first, so the client sees every message, and every balance, in order.
    if (this._deferred.length > 0) this.sendDeferred()
    holdWritesUntilEndOfTurn(this.socket)
    this._write(new OutgoingMessage(text))
    this.metrics.messagesOut.labels(type).inc()
    this.metrics.bytesOut.inc(Buffer.byteLength(text))
  }

  /**
   * The owner's `settled` of a drop in `room`: its feed there decides when
   * it goes (at once, or in the room's next frame: deliveries.js); from any
   * other room, or none, at once.
   * @param {string} text @param {import('../rooms/room.js').Room} room
   */
  sendSettled (text, room) {
    if (this.feed !== null && this.room === room) this.feed.ownerSettled(this, text)
    else this.sendEvent(text, 'settled')
  }

  /** Holds a `settled` for the room's next frame (the seeds delivery). @param {string} text */
  defer (text) {
    if (!this.closed) this._deferred.push(text)
  }

  /** The held messages for a frame, oldest first, counted as sent; null when none. @returns {string[] | null} */
  takeDeferred () {
    if (this._deferred.length === 0) return null
    const texts = this._deferred
    this._deferred = []
    this.metrics.messagesOut.labels('settled').inc(texts.length)
    return texts
  }

  /** Sends the held messages on their own (leaving the room, closing, or before any other message). */
  sendDeferred () {
    const texts = this._deferred
    this._deferred = []
    for (const text of texts) this.sendEvent(text, 'settled')
  }

  /**
   * The room's frame for this snapshot period. The snapshot in it may be
   * skipped (the next one supersedes it), its events may not: over the soft
   * limit, the events alone are sent, as `{type:"events"}`. The send queue
   * is read once per frame; the caller counts the frames written (one
   * metrics update per room, not per socket).
   * @param {OutgoingMessage} frame the room's, one for all its sockets @param {string | null} events the frame's events as an `events` message (JSON text), or null
   * @returns {boolean} the frame was written
   */
  sendRoomFrame (frame, events) {
    if (this.closed) return false
    const queued = this.socket.bufferedAmount
    if (queued > this.hardLimit) {
      this._tooSlow()
      return false
    }
    if (queued > this.softLimit) {
      this.metrics.snapshotsSkipped.inc()
      if (events !== null) this.sendEvent(events, 'events')
      return false
    }
    holdWritesUntilEndOfTurn(this.socket)
    return this._write(frame)
  }

  /**
   * A binary frame of events (the seeds delivery's drop-events frame): never
   * skipped, like any event; over the hard limit the client is closed. The
   * caller counts the frames written (one metrics update per room).
   * @param {OutgoingMessage} frame the room's (one for all its sockets), or this socket's copy with its own messages
   * @returns {boolean} the frame was written
   */
  sendEventFrame (frame) {
    if (this.closed) return false
    if (this.socket.bufferedAmount > this.hardLimit) {
      this._tooSlow()
      return false
    }
    holdWritesUntilEndOfTurn(this.socket)
    return this._write(frame)
  }

  /**
   * @param {string} code @param {string} [message] @param {any} [ref]
   * @param {object} [details] extra fields, e.g. `room` and `owner` of E_WRONG_NODE
   */
  sendError (code, message, ref, details) {
    this.metrics.errors.labels(code).inc()
    const error = errorMessage(code, message ?? ERROR_CODES[code].message, details)
    if (ref !== undefined) error.ref = ref
    this.sendJson(error)
  }

  _tooSlow () {
    this.metrics.slowConsumersClosed.inc()
    this.log.warn({ player: this.account?.playerId, buffered: this.socket.bufferedAmount }, 'closing slow consumer')
    this.drop(ERROR_CODES.E_SLOW_CONSUMER.close, 'E_SLOW_CONSUMER')
  }

  /** Over the frame rate (this connection's, or its address's): one reply, then the connection goes (1008). */
  _overRate (scope = 'per connection') {
    if (this.closed) return
    this.metrics.messagesIn.labels('rate_limited').inc()
    this.sendError('E_RATE_LIMITED', scope === 'per connection'
      ? `at most ${this.messageLimiter.rate} messages per second per connection; closing`
      : 'too many messages per second from this address (over all its connections); closing')
    this.drop(OVER_RATE_CLOSE, 'E_RATE_LIMITED')
  }

  // ---- lifecycle ------------------------------------------------------------

  /** Called every WS_HEARTBEAT_MS (30 s) by the arena: a peer that missed the previous ping is gone. */
  heartbeat () {
    if (!this.alive) {
      this.socket.terminate()
      return
    }
    this.alive = false
    this.socket.ping()
  }

  /** @param {number} code @param {string} reason */
  close (code, reason) {
    if (this.closed) return
    this.sendDeferred()
    this._closed()
    this.socket.close(code, reason)
  }

  /**
   * Closes a connection for abuse: the close frame goes out, nothing more is
   * read (a flooder's frames are not even parsed, those already received are
   * thrown away: discard-unread.js), and the socket is
   * destroyed DROP_GRACE_MS later whether or not the peer answers.
   * @param {number} code @param {string} reason
   */
  drop (code, reason) {
    if (this.closed) return
    this.close(code, reason)
    this.socket.pause()
    discardUnread(this.socket)
    setTimeout(() => {
      discardUnread(this.socket)
      this.socket.terminate()
    }, DROP_GRACE_MS).unref()
  }

  _closed () {
    if (this.closed) return
    this.closed = true
    this._early.length = 0
    if (this.account) {
      this.arena.disconnected(this)
      this.account.connections.delete(this)
      this.arena.accounts.release(this.account)
    }
  }
}

function withRef (message, ref) {
  if (ref !== undefined) message.ref = ref
  return message
}

// ---- reading a client frame ---------------------------------------------------

/** Which error code a schema failure on a given field is reported as. */
const FIELD_CODES = { '/bet': 'E_BAD_BET', '/clientSeed': 'E_BAD_SEED', '/room': 'E_UNKNOWN_ROOM', '/delivery': 'E_BAD_DELIVERY' }

/**
 * Compiles the schemas once; the returned function parses a text frame and
 * returns the message, or throws a GameError naming what is wrong.
 * @param {{ minBet: number, maxBet: number }} limits
 * @returns {(text: string) => { type: string, ref?: any, [key: string]: any }}
 */
export function createMessageParser (limits) {
  const ajv = new Ajv({ allErrors: false, strict: true })
  const validators = new Map(Object.entries(clientMessageSchemas(limits)).map(([type, schema]) => [type, ajv.compile(schema)]))
  return function parseClientMessage (text) {
    let message
    try {
      message = JSON.parse(text)
    } catch {
      throw gameError('E_BAD_MESSAGE', 'message is not valid JSON')
    }
    if (message === null || typeof message !== 'object' || Array.isArray(message) || typeof message.type !== 'string') {
      throw gameError('E_BAD_MESSAGE', 'message must be a JSON object with a string "type"')
    }
    const validate = validators.get(message.type)
    if (!validate) throw gameError('E_UNKNOWN_TYPE', `unknown message type ${JSON.stringify(message.type.slice(0, 32))}; known: ${[...validators.keys()].join(', ')}`, { ref: echoableRef(message.ref) })
    if (!validate(message)) {
      const [error] = validate.errors
      const code = FIELD_CODES[error.instancePath] ?? 'E_BAD_MESSAGE'
      const where = error.instancePath === '' ? message.type : `${message.type}${error.instancePath.replaceAll('/', '.')}`
      throw gameError(code, `${where} ${error.message}`, { ref: echoableRef(message.ref) })
    }
    return message
  }
}

/** A ref worth echoing back even when the rest of the message is wrong. */
function echoableRef (value) {
  if ((typeof value === 'string' && value.length <= 64) || Number.isSafeInteger(value)) return value
  return undefined
}
