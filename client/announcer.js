import { formatAmount, formatMultiplier, formatSigned } from './dom.js'

/** Announcements kept for tests (the latest). */
const KEPT = 50

/**
 * A polite live region (`aria-live="polite"`): what screen readers read
 * out without interrupting — each of the player's own results and
 * auto-bet's end. Each announcement replaces the last.
 */
export class Announcer {
  /** @param {HTMLElement} region */
  constructor (region) {
    this.region = region
    /** @type {string[]} latest last */
    this.said = []
  }

  /** @param {string} text */
  say (text) {
    this.region.textContent = text
    this.said.push(text)
    if (this.said.length > KEPT) this.said.shift()
  }

  /** One of the player's results. @param {{ dropId: number, bet: number, multiplier: number, payout: number }} result */
  result ({ dropId, bet, multiplier, payout }) {
    this.say(`Drop ${dropId}: ${formatMultiplier(multiplier)}, paid ${formatAmount(payout)} on a bet of ${formatAmount(bet)} (${formatSigned(payout - bet)}).`)
  }
}
