import { ENGINE_VERSIONS } from '../../engine/index.js'
import { encodeDropEvents, withOwnMessages, FlightHasher } from '../../protocol/drop-events-codec.js'
import { OutgoingMessage } from './outgoing-message.js'

/** At most this long (seconds) between two desync checks while balls are in flight. */
export const DESYNC_CHECK_SECONDS = 2

/**
 * Frames a tick writes (all rooms, both deliveries) past which a frame
 * held for a commit that is now done waits one more tick. A commit ends
 * for every room at once: at 6,000 players the rooms holding for a slow one
 * released 2,000–3,200 socket frames in one tick, 6–9 ms of it, most of the
 * ticks over 8 ms. Spread over the next ticks instead, a few at a time; a
 * frame held half a period goes whatever the count.
 */
export const RELEASED_FRAMES_PER_TICK = 1000

/**
 * The `seeds` delivery: the page simulates every ball from its drop seed,
 * so its sockets get no positions. Its own drops' `dropped` (with the
 * balance) reaches the owner at once, as in every mode (drop-lifecycle.js);
 * this feed sends the room's drop-events frames (protocol/drop-events-codec.js,
 * encoded once per room): the drops announced since the last frame, on
 * ticks where (tick + phase) is a multiple of eventEvery (60 / EVENT_HZ), and
 * on such a tick with nothing announced, a desync check alone when balls are
 * in flight and none went out for checkEvery ticks. The owner's `settled`
 * (with the balance) rides in its copy of the room's next frame (the
 * owner's section), at most 1/EVENT_HZ after it was credited: the page has
 * seen the ball land by then, and a frame less per drop is a write less
 * per socket. Held messages go out on their own first whenever anything
 * else is sent to that socket, or it leaves or closes, so its messages and
 * balances keep their order (Connection.sendDeferred). A due frame waits
 * while a drop released before its tick is still being committed, for at
 * most half a period: sent as soon as that commit is done (batchCommitted,
 * between two ticks, not at the next tick), the drop reaches the room then
 * instead of a period later (the commit overlaps the wait for the frame);
 * still one frame a period. It does not wait once a drop it carries has
 * waited more than a period (accepted just after the last frame): that
 * drop would then reach the room later than the one being committed will
 * in the next frame, and such drops are the tail of the room's sighting.
 * Frames released that way wait a tick more while RELEASED_FRAMES_PER_TICK
 * frames have been written since the last tick began, so the rooms a
 * commit held do not all go at once.
 * Nothing else: a room
 * where nothing happens sends nothing. Other players' settlements are not
 * sent (the page computes the landing; the facts are fetched on demand).
 * @type {import('./deliveries.js').Delivery}
 */
export const seedsDelivery = {
  name: 'seeds',
  createFeed: (room) => new SeedFeed(room),
  joinedFields: (room) => ({ eventEvery: room.eventEvery, checkEvery: room.checkEvery, engineVersions: ENGINE_VERSIONS })
}

class SeedFeed {
  /** @param {import('../rooms/room.js').Room} room */
  constructor (room) {
    this.room = room
    /** @type {Set<import('./connection.js').Connection>} */
    this.clients = new Set()
    /** @type {import('../game/drop.js').Drop[]} announced since the last frame, oldest first */
    this.pending = []
    this.lastFrameTick = -Infinity
    this.hasher = new FlightHasher()
    /** Sockets holding a `settled` for the next frame. @type {Set<import('./connection.js').Connection>} */
    this.owed = new Set()
    /** The due tick of a frame held for drops still being committed, or -1. */
    this.heldSince = -1
    /** Most ticks a due frame is held (half a period: then it goes with what is announced). */
    this.maxHold = room.eventEvery >> 1
  }

  /** @param {import('./connection.js').Connection} client @param {string} text */
  ownerSettled (client, text) {
    client.defer(text)
    this.owed.add(client)
  }

  /** @param {import('./connection.js').Connection} client */
  leave (client) {
    this.clients.delete(client)
    this.owed.delete(client)
    client.sendDeferred()
  }

  dropAnnounced (drop) {
    if (this.clients.size > 0) this.pending.push(drop)
  }

  dropSettled () {}

  /** Nothing to flush: a drop queued now comes again in the next frame, and the joiner skips it by id. */
  beforeJoin () {}

  flushNow () {}

  /**
   * A batch with drops of this room was committed (or refused): a frame held
   * for them goes now rather than at the next tick, a tick's wait less for
   * every drop in it (about half a tick on average, up to a whole one).
   * @param {import('./deliveries.js').DeliveryTally} tally
   */
  batchCommitted (tally) {
    if (this.heldSince < 0 || this.room.awaitsCommitBefore(this.heldSince) || framesOf(tally) >= RELEASED_FRAMES_PER_TICK) return
    this.heldSince = -1
    this._send(tally)
  }

  /** @param {import('./deliveries.js').DeliveryTally} tally */
  afterTick (tally) {
    const room = this.room
    const tick = room.tick
    if (this.clients.size === 0) {
      // Nobody to tell: a later joiner gets these balls in `joined` instead.
      this.pending.length = 0
      this.heldSince = -1
      return
    }
    if (this.heldSince >= 0) {
      if (tick - this.heldSince < this.maxHold && ((this._mayWait(tick) && room.awaitsCommitBefore(this.heldSince)) || framesOf(tally) >= RELEASED_FRAMES_PER_TICK)) return
      this.heldSince = -1
    } else {
      if ((tick + room.snapshotPhase) % room.eventEvery !== 0) return
      if (this.maxHold > 0 && this._mayWait(tick) && room.awaitsCommitBefore(tick)) {
        this.heldSince = tick
        return
      }
    }
    this._send(tally)
  }

  /**
   * Whether the frame may still wait for a commit: not once a drop it
   * carries has waited more than a period (one accepted just after the last
   * frame), or it would reach the room later than a drop that misses this
   * frame and goes in the next.
   * @param {number} tick
   */
  _mayWait (tick) {
    const oldest = tick - this.room.eventEvery
    for (let i = 0; i < this.pending.length; i++) if (this.pending[i].startTick < oldest) return false
    return true
  }

  /** Sends the room's frame (and the owners' sections) now, if there is anything to send. @param {import('./deliveries.js').DeliveryTally} tally */
  _send (tally) {
    const room = this.room
    const tick = room.tick
    const forEveryone = this.pending.length > 0 || (room.visibleCount > 0 && tick - this.lastFrameTick >= room.checkEvery)
    if (!forEveryone && this.owed.size === 0) return
    // A period's drops fit one frame: at most MAX_BALLS_PER_ROOM (≤ 4,096) are in flight,
    // and no ball lands within one period (≤ 1 s), far below MAX_EVENTS_PER_FRAME.
    const frame = encodeDropEvents(tick, this._flightHash(), this.pending)
    // Framed for the wire once, on the first socket that takes it as it is.
    const shared = new OutgoingMessage(frame)
    // A frame of one player's drops alone tells that player nothing it has not had in its `dropped`.
    const onlyDropsOf = soleDropper(this.pending)
    this.pending.length = 0
    if (forEveryone) this.lastFrameTick = tick
    let written = 0
    let bytes = 0
    const owed = this.owed
    for (const client of forEveryone ? this.clients : owed) {
      const own = owed.size > 0 ? client.takeDeferred() : null
      // Nothing for it: what it was owed went out on its own since, or the frame holds its own drops only.
      if (own === null && (!forEveryone || client.account === onlyDropsOf)) continue
      const copy = own === null ? shared : new OutgoingMessage(withOwnMessages(frame, own))
      if (client.sendEventFrame(copy)) { written++; bytes += copy.payload.length }
    }
    owed.clear()
    tally.eventFrames += written
    tally.eventBytes += bytes
  }

  /** The flight hash (drop-events-codec.js) of the room's visible balls at its current tick. */
  _flightHash () {
    const room = this.room
    const world = room.simulator.world
    const hasher = this.hasher.begin(room.tick)
    const visible = room.visible
    for (let slot = 0, count = world.bodyCount; slot < count; slot++) {
      if (visible[slot] === 1) hasher.add(slot, world.xOf(slot), world.yOf(slot), world.vxOf(slot), world.vyOf(slot))
    }
    return hasher.digest()
  }
}

/**
 * The account whose drops are all of `drops`, or null (none, or several players').
 * @param {import('../game/drop.js').Drop[]} drops
 */
function soleDropper (drops) {
  if (drops.length === 0) return null
  const account = drops[0].account
  for (let i = 1; i < drops.length; i++) if (drops[i].account !== account) return null
  return account
}

/** Frames written so far in this tick, by every feed. @param {import('./deliveries.js').DeliveryTally} tally */
function framesOf (tally) {
  return tally.eventFrames + tally.snapshotFrames
}
