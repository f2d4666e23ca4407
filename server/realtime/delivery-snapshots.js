import { BODY_STRIDE, BODY_X, BODY_Y } from '../../engine/index.js'
import { encodeSnapshot, encodeRoomFrame } from '../../protocol/snapshot-codec.js'
import { eventsMessageText } from '../../protocol/server-messages.js'
import { OutgoingMessage } from './outgoing-message.js'

/**
 * The `snapshots` delivery (the default): every `snapshotEvery` ticks the
 * room's visible balls' positions (protocol/snapshot-codec.js), with the
 * period's `dropped`/`settled` events of everyone in the same binary room
 * frame, encoded once per room. For thin clients and anything that cannot
 * run the engine.
 * @type {import('./deliveries.js').Delivery}
 */
export const snapshotsDelivery = {
  name: 'snapshots',
  createFeed: (room) => new SnapshotFeed(room),
  joinedFields: () => ({})
}

class SnapshotFeed {
  /** @param {import('../rooms/room.js').Room} room */
  constructor (room) {
    this.room = room
    /** @type {Set<import('./connection.js').Connection>} */
    this.clients = new Set()
    /** `dropped`/`settled` (JSON text) for this feed's sockets, sent with the next snapshot. */
    this.pendingEvents = []
    this._lastSnapshotHadBalls = false
  }

  dropAnnounced (drop, text) { this._queue(text) }
  dropSettled (drop, text) { this._queue(text) }

  /** The owner's `settled` goes at once: its next room frame may be skipped (sendRoomFrame). */
  ownerSettled (client, text) { client.sendEvent(text, 'settled') }

  /** @param {import('./connection.js').Connection} client */
  leave (client) { this.clients.delete(client) }

  _queue (text) {
    if (this.clients.size > 0) this.pendingEvents.push(text)
  }

  /** Events queued so far concern balls the joiner gets in `balls`: the others get them now. */
  beforeJoin () { this._sendQueuedEvents() }

  flushNow () { this._sendQueuedEvents() }

  /** Nothing waits for a commit here: a snapshot goes on its tick with what was announced by then. */
  batchCommitted () {}

  /** @param {import('./deliveries.js').DeliveryTally} tally */
  afterTick (tally) {
    const room = this.room
    if (this.clients.size === 0 || (room.tick + room.snapshotPhase) % room.snapshotEvery !== 0) return
    const events = this._takeEvents()
    const snapshot = this._encodeSnapshot()
    if (snapshot === null) {
      if (events !== null) this._sendEvents(events)
      return
    }
    const frame = new OutgoingMessage(events === null ? snapshot : encodeRoomFrame(events, snapshot))
    const eventsText = events === null ? null : eventsMessageText(room.id, events)
    let written = 0
    for (const client of this.clients) if (client.sendRoomFrame(frame, eventsText)) written++
    tally.snapshotFrames += written
    tally.snapshotBytes += written * frame.payload.length
  }

  _sendQueuedEvents () {
    const events = this._takeEvents()
    if (events !== null) this._sendEvents(events)
  }

  /** @param {string} events a JSON array text from _takeEvents() */
  _sendEvents (events) {
    const text = eventsMessageText(this.room.id, events)
    for (const client of this.clients) client.sendEvent(text, 'events')
  }

  /** The queued events as one JSON array text, or null if none; clears the queue. */
  _takeEvents () {
    if (this.pendingEvents.length === 0) return null
    const json = `[${this.pendingEvents.join(',')}]`
    this.pendingEvents.length = 0
    return json
  }

  /** The snapshot frame for the current tick, or null when there is nothing new to say (no balls now and none in the previous frame). */
  _encodeSnapshot () {
    const room = this.room
    if (room.visibleCount === 0 && !this._lastSnapshotHadBalls) return null
    this._lastSnapshotHadBalls = room.visibleCount > 0
    const world = room.simulator.world
    return encodeSnapshot(room.tick, room.visible, world.bodyCount, world.state, world.state, BODY_STRIDE, BODY_X, BODY_Y)
  }
}
