import { settleInterruptedDrops } from '../game/recovery.js'

/**
 * The coordinator of a server that runs alone (coordinator.js): it owns
 * its ledger, so every room is its own, drop ids continue from the
 * ledger's highest, each seed's nonces are counted on the account, and
 * every drop left in flight by the last run is settled at start.
 * @implements {import('./coordinator.js').Coordinator}
 */
export class LocalCoordinator {
  /** @param {{ store: any, log: import('pino').Logger }} options */
  constructor ({ store, log }) {
    this.store = store
    this.log = log
    this.arena = null
    this.nextDropId = 1
  }

  /** @param {import('../arena.js').Arena} arena */
  async start (arena) {
    this.arena = arena
    this.nextDropId = (await this.store.maxDropId()) + 1
    await settleInterruptedDrops(this.store, this.log)
  }

  ownsRoom () { return true }
  async claimRoom () {}
  roomDisposed () {}
  takeNonce (seed) { return seed.nextNonce++ }
  takeDropId () { return this.nextDropId++ }
  balancesCommitted () {}
  async seedRotated () {}
  async seedOutdated () {}
  async listRooms () { return [...this.arena.rooms.values()].map((room) => room.summary()) }
  setListenUrl () {}
  async close () {}
}
