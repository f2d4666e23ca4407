import { byId, showAmount } from './dom.js'

/** The player as the server knows them: id, balance (shown in the header), and the table's bet limits. */
export class PlayerAccount {
  constructor () {
    /** @type {string | null} */
    this.playerId = null
    /** @type {number | null} */
    this.balance = null
    this.minBet = 1
    this.maxBet = Infinity
  }

  /** @param {number} balance */
  setBalance (balance) {
    this.balance = balance
    showAmount(byId('balance'), balance)
  }
}
