import { Room } from './room.js'
import { parseRoomId, ROOM_INSTANCES } from '../../protocol/room-id.js'
import { boardOf } from './boards.js'
import { gameError } from '../errors.js'

/**
 * The rooms alive in this process, by id, in creation order. Creates a room
 * on its first join and disposes it once it is idle (no clients, no balls in
 * flight). The arena steps them board by board (inStepOrder).
 */
export class RoomRegistry {
  /**
   * @param {object} options
   * @param {number} options.snapshotEvery ticks between snapshots
   * @param {number} [options.eventEvery] ticks between drop-events frames (seeds delivery)
   * @param {number} [options.checkEvery] most ticks between desync checks
   * @param {(room: Room) => void} [options.onChange] after a room is created or disposed
   */
  constructor ({ snapshotEvery, eventEvery, checkEvery, onChange = () => {} }) {
    this.snapshotEvery = snapshotEvery
    this.eventEvery = eventEvery
    this.checkEvery = checkEvery
    this.onChange = onChange
    /** @type {Map<string, Room>} */
    this.rooms = new Map()
    this._created = 0
    /** @type {Room[] | null} the rooms grouped by board, rebuilt after a change */
    this._stepOrder = null
  }

  /** @param {string} id */
  get (id) {
    return this.rooms.get(id)
  }

  /**
   * @param {unknown} id
   * @returns {Room}
   * @throws E_UNKNOWN_ROOM when `id` names no board
   */
  getOrCreate (id) {
    const existing = this.rooms.get(/** @type {string} */ (id))
    if (existing) return existing
    if (!parseRoomId(id)) throw gameError('E_UNKNOWN_ROOM', `no room ${JSON.stringify(id)}; room ids are ROWS-RISK or ROWS-RISK.N (N = 2..${ROOM_INSTANCES}), e.g. 16-medium or 16-medium.2`)
    const room = new Room({
      id: /** @type {string} */ (id),
      board: boardOf(/** @type {string} */ (id)),
      snapshotEvery: this.snapshotEvery,
      eventEvery: this.eventEvery,
      checkEvery: this.checkEvery,
      snapshotPhase: this._created++
    })
    this._add(room)
    return room
  }

  /** Adds a room built elsewhere (benchmarks run many rooms per board). @param {Room} room */
  adopt (room) {
    this._add(room)
  }

  /**
   * The rooms in the order a tick steps them: those on one board one after
   * another (boards in the order their first room was created, rooms in
   * creation order within a board), so a board's pegs and grid are read
   * from the CPU's cache by all its rooms' balls in a row rather than
   * fetched again for each room. The order decides no outcome.
   * @returns {readonly Room[]}
   */
  inStepOrder () {
    if (this._stepOrder === null) {
      const byBoard = new Map()
      for (const room of this.rooms.values()) {
        const rooms = byBoard.get(room.board)
        if (rooms) rooms.push(room)
        else byBoard.set(room.board, [room])
      }
      this._stepOrder = [...byBoard.values()].flat()
    }
    return this._stepOrder
  }

  /** @param {Room} room */
  _add (room) {
    this.rooms.set(room.id, room)
    this._stepOrder = null
    this.onChange(room)
  }

  /** @param {Room} room */
  _delete (room) {
    this.rooms.delete(room.id)
    this._stepOrder = null
    this.onChange(room)
  }

  /** Removes a room whatever its state (it moved to another process). @param {string} id @returns {Room | undefined} */
  remove (id) {
    const room = this.rooms.get(id)
    if (!room) return undefined
    this._delete(room)
    return room
  }

  disposeIdle () {
    for (const room of this.rooms.values()) {
      if (!room.isIdle) continue
      this._delete(room)
    }
  }

  values () {
    return this.rooms.values()
  }

  get size () { return this.rooms.size }
}
