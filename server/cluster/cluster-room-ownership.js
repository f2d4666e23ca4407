import { parseRoomId } from '../../protocol/room-id.js'
import { GameError, gameError } from '../errors.js'
import { settleInterruptedDrops } from '../game/recovery.js'
import { RedisRoomDirectory, KEYS } from './room-directory.js'

/**
 * Room ownership of a process in a cluster (../coordination/room-ownership.js):
 * it owns rooms through leases in Redis, renews them (and its presence and
 * room summaries) every TTL/3, gives a room's lease back once the room is
 * disposed and its ledger writes are committed, settles the drops of rooms
 * left by dead processes, and reports a lease lost (`onRoomLost`).
 *
 * Takeover: a room whose lease expired (its owner died) is claimed by the
 * first process a player joins it on, or by the sweep (every TTL) if drops
 * of it are still in flight in the ledger. Before the room runs again its
 * in-flight drops are replayed from their seeds and settled, each at most
 * once (the shared ledger's `WHERE status = 'in_flight'`).
 * @implements {import('../coordination/room-ownership.js').RoomOwnership}
 */
export class ClusterRoomOwnership {
  /**
   * @param {object} options
   * @param {import('./cluster-presence.js').ClusterPresence} options.presence
   * @param {import('./shared-ledger.js').SharedLedgerStore} options.store
   * @param {import('../config.js').Config} options.config
   * @param {import('pino').Logger} options.log
   */
  constructor ({ presence, store, config, log }) {
    this.presence = presence
    this.store = store
    this.log = log
    this.ttlMs = config.leaseTtlMs
    this.nodeId = presence.nodeId
    this.publicUrl = config.publicUrl
    this.redis = presence.redis
    /** @type {import('../coordination/room-ownership.js').OwnershipServices | null} the rooms here, the ledger queue, onRoomLost */
    this.services = null
    this.directory = null
    /** Rooms whose lease we hold. */
    this.owned = new Set()
    /** Per room: the tail of its claim/release chain (they never overlap). */
    this._chains = new Map()
    this._timers = []
    this.closed = false
    this.stats = { takeovers: 0, recovered: 0 }
    /** When the leases were last renewed (or, before that, taken). */
    this.renewedAt = Date.now()
  }

  /**
   * Connects to Redis, advertises this process, settles orphaned drops and
   * starts the timers. @param {import('../coordination/room-ownership.js').OwnershipServices} services
   */
  async start (services) {
    this.services = services
    const { rooms } = services
    this.directory = new RedisRoomDirectory({
      redis: this.redis,
      nodeId: this.nodeId,
      publicUrl: () => this.publicUrl,
      ttlMs: this.ttlMs,
      localSummaries: () => [...rooms.values()].map((room) => room.summary())
    })
    await this.presence.connect()
    await this.directory.publish([])
    await this.sweep()
    const every = (ms, job) => {
      const timer = setInterval(() => { job().catch((error) => this.log.error({ err: error }, 'cluster job failed')) }, ms)
      timer.unref()
      this._timers.push(timer)
    }
    every(Math.max(100, Math.floor(this.ttlMs / 3)), () => this.heartbeat())
    every(this.ttlMs, () => this.sweep())
  }

  /** @param {string} roomId */
  owns (roomId) { return this.owned.has(roomId) }

  /** Every room running in the cluster, with the URL of the process that runs it. */
  list () { return this.directory.list() }

  /** Called once the HTTP server listens, when PUBLIC_URL was not set. @param {string} url */
  setListenUrl (url) {
    if (!this.publicUrl) this.publicUrl = url
  }

  /**
   * Takes a room this process does not run yet: claims its lease (taking it
   * over if its owner died), or refuses with where the room runs.
   * @param {string} roomId a valid room id
   */
  async claim (roomId) {
    let claim
    try {
      claim = await this._take(roomId)
    } catch (error) {
      if (error instanceof GameError) throw error
      // Redis (or the ledger) did not answer: the room may be anyone's; the player retries, as after a takeover.
      this.log.warn({ err: error, room: roomId }, 'cannot claim room: coordination store unavailable')
      throw withDetails(gameError('E_ROOM_MOVING', 'rooms cannot be claimed right now (the cluster\'s Redis does not answer); retry after `retryAfterMs`'), { room: roomId, retryAfterMs: this.ttlMs })
    }
    if (claim.held) return
    if (claim.owner) throw withDetails(gameError('E_WRONG_NODE', `room ${roomId} runs on ${claim.owner}; connect to ${claim.owner}/ws and join again`), { room: roomId, owner: claim.owner })
    throw withDetails(gameError('E_ROOM_MOVING'), { room: roomId, retryAfterMs: claim.retryAfterMs })
  }

  /** @param {string} roomId @returns {Promise<{ held: boolean, owner?: string | null, retryAfterMs?: number }>} */
  _take (roomId) {
    if (this.owned.has(roomId)) return Promise.resolve({ held: true })
    return this._serial(roomId, async () => {
      if (this.owned.has(roomId)) return { held: true }
      if (this.closed) throw gameError('E_UNAVAILABLE')
      const claim = await this.directory.claim(roomId)
      if (!claim.held) return claim
      if (this.owned.size === 0) this.renewedAt = Date.now()
      this.owned.add(roomId)
      if (!this.services.rooms.get(roomId)) await this._recover(roomId)
      return claim
    })
  }

  /** Settles the in-flight drops a previous owner left in this room (each at most once). */
  async _recover (roomId) {
    const drops = await this.store.listInFlightDropsOfRoom(roomId)
    if (drops.length === 0) return
    let settled
    for (let attempt = 1; ; attempt++) {
      try {
        ({ settled } = await settleInterruptedDrops(this.store, this.log, { drops }))
        break
      } catch (error) {
        // Another process settling the same drops at the same moment: its rows win, ours are skipped on retry.
        if (attempt >= 3) throw error
        this.log.warn({ err: error, room: roomId, attempt }, 'settling a taken-over room failed; retrying')
      }
    }
    this.stats.takeovers++
    this.stats.recovered += settled
    this.log.warn({ room: roomId, settled, found: drops.length }, 'took over a room and settled its drops in flight')
  }

  /**
   * The arena disposed an idle room: give its lease back once everything
   * written for it so far is committed (so the next owner finds no drop of
   * ours in flight), unless the room came back meanwhile.
   * @param {string} roomId
   */
  disposed (roomId) {
    if (this.closed) return
    this.services.ledger.run(() => this._serial(roomId, async () => {
      if (this.services.rooms.get(roomId) || !this.owned.has(roomId)) return
      this.owned.delete(roomId)
      await this.directory.release(roomId)
    })).catch((error) => this.log.error({ err: error, room: roomId }, 'could not release a room lease'))
  }

  /** Renews our leases (evicting rooms lost meanwhile), presence and summaries. */
  async heartbeat () {
    if (this.closed) return
    // Fencing: leases we could not renew for most of a TTL may already be someone else's.
    if (this.owned.size > 0 && Date.now() - this.renewedAt > this.ttlMs * 0.9) {
      for (const roomId of [...this.owned]) this._evict(roomId)
    }
    const started = Date.now()
    const lost = await this.directory.renew([...this.owned])
    this.renewedAt = started
    for (const roomId of lost) this._evict(roomId)
    await this.directory.publish([...this.services.rooms.values()].map((room) => room.summary()))
  }

  /**
   * Our lease passed to another process (we stalled past the TTL): stop
   * running the room (onRoomLost: the arena tells its players to move,
   * refuses its unrecorded drops and settles the recorded ones).
   */
  _evict (roomId) {
    this.owned.delete(roomId)
    this.log.error({ room: roomId }, 'lost the lease of a room to another process')
    this.services.onRoomLost(roomId)
  }

  /** Rooms with drops in flight and no owner: claim them (which settles the drops), then let them go. */
  async sweep () {
    if (this.closed) return
    const rooms = await this.store.listRoomsWithDropsInFlight()
    for (const roomId of rooms) {
      if (this.owned.has(roomId) || !parseRoomId(roomId)) continue
      if (await this.redis.exists(KEYS.lease(roomId))) continue
      const claim = await this._take(roomId)
      if (claim.held && !this.services.rooms.get(roomId)) this.disposed(roomId)
    }
  }

  /** After the arena has settled and committed everything: give every lease back (the presence closes the connection). */
  async close () {
    if (this.closed) return
    this.closed = true
    for (const timer of this._timers) clearInterval(timer)
    if (!this.directory) return
    try {
      await Promise.all([...this._chains.values()])
      for (const roomId of [...this.owned]) await this.directory.release(roomId)
      this.owned.clear()
      await this.redis.del(KEYS.node(this.nodeId))
    } catch (error) {
      this.log.warn({ err: error }, 'leaving the cluster failed; leases expire after their TTL')
    }
  }

  _serial (roomId, job) {
    const previous = this._chains.get(roomId) ?? Promise.resolve()
    const result = previous.then(job, job)
    const tail = result.then(noop, noop)
    this._chains.set(roomId, tail)
    tail.then(() => { if (this._chains.get(roomId) === tail) this._chains.delete(roomId) })
    return result
  }
}

function withDetails (error, details) {
  error.details = details
  return error
}

function noop () {}
