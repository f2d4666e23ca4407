import { settleInterruptedDrops } from '../game/recovery.js'

/**
 * Room ownership of a server that runs alone (room-ownership.js): it owns
 * its ledger, so every room is its own, and every drop left in flight by
 * the last run is settled at start.
 * @implements {import('./room-ownership.js').RoomOwnership}
 */
export class LocalRoomOwnership {
  /** @param {{ store: import('../store/ledger-store.js').LedgerStore, log: import('pino').Logger }} options */
  constructor ({ store, log }) {
    this.store = store
    this.log = log
    this.rooms = null
  }

  /** @param {import('./room-ownership.js').OwnershipServices} services */
  async start ({ rooms }) {
    this.rooms = rooms
    await settleInterruptedDrops(this.store, this.log)
  }

  owns () { return true }
  async claim () {}
  disposed () {}
  async list () { return [...this.rooms.values()].map((room) => room.summary()) }
  setListenUrl () {}
  async close () {}
}
