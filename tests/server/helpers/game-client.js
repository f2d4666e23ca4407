import WebSocket from 'ws'
import { decodeSnapshot, splitRoomFrame } from '../../../protocol/snapshot-codec.js'
import { decodeDropEvents, DROP_EVENTS_KIND } from '../../../protocol/drop-events-codec.js'

/**
 * A test player on a real WebSocket. Every JSON message and decoded
 * snapshot is kept in arrival order (the other players' events that come
 * batched, in a room frame or an `events` message, are unpacked in place); take() waits for the first message
 * not yet taken that matches, so tests read the protocol like a script.
 */
export class GameClient {
  /** @param {string} url */
  constructor (url) {
    this.socket = new WebSocket(url)
    this.messages = []
    this.snapshots = []
    /** how the room's events arrived: { via: 'room frame' | 'events', events } */
    this.batches = []
    /** seeds delivery: decoded drop-events frames, { tick, hash, events, bytes, at } (at: ms, performance.now()) */
    this.eventFrames = []
    this.taken = new Set()
    this.waiters = []
    this.closeEvent = null
    this.opened = new Promise((resolve, reject) => {
      this.socket.once('open', resolve)
      this.socket.once('error', reject)
    })
    this.closed = new Promise((resolve) => {
      this.socket.once('close', (code, reason) => {
        this.closeEvent = { code, reason: reason.toString() }
        resolve(this.closeEvent)
        this._notify()
      })
    })
    this.socket.on('message', (data, isBinary) => {
      if (isBinary && data[0] === DROP_EVENTS_KIND) {
        const frame = decodeDropEvents(data)
        this.eventFrames.push({ ...frame, bytes: data.length, at: performance.now() })
        // The owner's section: this player's own messages, as if each had come on its own.
        for (const message of frame?.own ?? []) this.messages.push({ ...message, viaFrame: frame.tick })
      } else if (isBinary) {
        // A room frame's events read as if each had come on its own, before the snapshot.
        const { events, snapshot } = splitRoomFrame(data)
        if (events.length > 0) this.batches.push({ via: 'room frame', events })
        this._roomEvents(events)
        this.snapshots.push({ ...decodeSnapshot(snapshot), bytes: data.length })
      } else {
        const message = JSON.parse(data.toString())
        if (message.type === 'events') {
          this.batches.push({ via: 'events', events: message.events })
          this._roomEvents(message.events)
        }
        else this.messages.push(message)
      }
      this._notify()
    })
  }

  /** Connects and waits for `welcome`. @param {string} url */
  static async connect (url) {
    const client = new GameClient(url)
    await client.opened
    client.welcome = await client.take('welcome')
    return client
  }

  send (message) {
    this.socket.send(typeof message === 'string' ? message : JSON.stringify(message))
  }

  /**
   * @param {string | ((message: any) => boolean)} match a type or a predicate
   * @param {number} [timeoutMs]
   */
  take (match, timeoutMs = 30_000) {
    const predicate = typeof match === 'string' ? (m) => m.type === match : match
    return new Promise((resolve, reject) => {
      const waiter = { predicate, resolve, reject }
      waiter.timer = setTimeout(() => {
        this.waiters.splice(this.waiters.indexOf(waiter), 1)
        reject(new Error(`timed out waiting for ${typeof match === 'string' ? match : 'a matching message'}; received: ${JSON.stringify(this.messages.map((m) => m.type))}`))
      }, timeoutMs)
      this.waiters.push(waiter)
      this._notify()
    })
  }

  /** Sends `request` and returns the next error message. */
  async expectError (request) {
    this.send(request)
    return this.take('error')
  }

  /** Round trip: everything sent before has been handled once the pong arrives. */
  async sync () {
    const ref = `sync-${Math.random()}`
    this.send({ type: 'ping', ref })
    await this.take((m) => m.type === 'pong' && m.ref === ref)
  }

  /** The room's events, less this player's own (those come on their own, with the balance). */
  _roomEvents (events) {
    for (const event of events) if (event.player !== this.welcome?.playerId) this.messages.push(event)
  }

  _notify () {
    for (const waiter of [...this.waiters]) {
      const index = this.messages.findIndex((m, i) => !this.taken.has(i) && waiter.predicate(m))
      if (index < 0) continue
      this.taken.add(index)
      clearTimeout(waiter.timer)
      this.waiters.splice(this.waiters.indexOf(waiter), 1)
      waiter.resolve(this.messages[index])
    }
  }

  async close () {
    if (this.socket.readyState === WebSocket.OPEN || this.socket.readyState === WebSocket.CONNECTING) this.socket.close()
    await this.closed
  }
}
