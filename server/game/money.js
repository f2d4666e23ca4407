import { MILLI_PER_CREDIT, PAYOUT_RULE, payoutMilli, toCredits, toMilli } from '../../protocol/payout.js'

/**
 * The money rules, in one place: what a drop costs, what a landing pays,
 * and how a batch of them changes each player's balance. The ledger batch
 * (drop.js) and the balances the players are shown (drop-lifecycle.js)
 * both come from here, so the database and the messages cannot disagree.
 *
 * Units: balances, reservations and payouts are integer milli-credits, in
 * memory and in the ledger; a bet is whole credits. What players and
 * operators see is credits with up to three decimals (`toCredits`). The
 * payout itself is protocol/payout.js, which the pages use to check it.
 */

export { PAYOUT_RULE, toCredits, toMilli }

/** Milli-credits a bet of `bet` whole credits costs. @param {number} bet */
export function betCost (bet) {
  return bet * MILLI_PER_CREDIT
}

/**
 * Milli-credits paid for a bet at a multiplier, under the drop's payout
 * rule (default: the one new drops are paid under).
 * @param {number} bet whole credits @param {number} multiplier @param {number} [rule]
 */
export function payoutFor (bet, multiplier, rule = PAYOUT_RULE) {
  return payoutMilli(bet, multiplier, rule)
}

/**
 * Each player's net balance change (milli-credits) from a batch: an
 * accepted drop debits its bet's cost, a settled landing credits its payout. Without `outcome` every drop and
 * settlement counts (what the batch asks the ledger to write); with it, only
 * what the ledger committed (a shared ledger may refuse a drop, or find a
 * drop already settled by another process).
 * @param {{ playerId: string, bet: number, id: number }[]} drops
 * @param {{ drop: { playerId: string, id: number }, payout: number }[]} settlements
 * @param {CommitOutcome} [outcome]
 * @returns {Map<string, number>} player id → change (entries may be 0)
 */
export function balanceChanges (drops, settlements, outcome) {
  const changes = new Map()
  for (const drop of drops) {
    if (outcome?.rejected.has(drop.id)) continue
    changes.set(drop.playerId, (changes.get(drop.playerId) ?? 0) - betCost(drop.bet))
  }
  for (const { drop, payout } of settlements) {
    if (outcome && !outcome.settled.has(drop.id)) continue
    changes.set(drop.playerId, (changes.get(drop.playerId) ?? 0) + payout)
  }
  return changes
}

/**
 * What the ledger debits per player for a set of new drops (each bet's
 * cost) and credits per player for a set of settled landings (each payout),
 * milli-credits: the shared ledger's conditional debits and its credits
 * (cluster/shared-ledger.js) come from here.
 * @param {{ playerId: string, bet: number }[]} drops
 * @returns {Map<string, number>}
 */
export function betTotals (drops) {
  const totals = new Map()
  for (const drop of drops) totals.set(drop.playerId, (totals.get(drop.playerId) ?? 0) + betCost(drop.bet))
  return totals
}

/**
 * @param {{ playerId: string, payout: number }[]} landings payout in milli-credits
 * @returns {Map<string, number>} only players paid more than 0
 */
export function payoutTotals (landings) {
  const totals = new Map()
  for (const { playerId, payout } of landings) if (payout > 0) totals.set(playerId, (totals.get(playerId) ?? 0) + payout)
  return totals
}

/**
 * A player's balance message by message through one committed batch:
 * starting from the committed balance less the batch's own changes, each
 * debit and credit is applied in the order the messages go out, so a
 * player's `dropped`/`settled` messages add up one by one and the last
 * shows exactly what the ledger holds.
 */
export class RunningBalances {
  /**
   * @param {Parameters<typeof balanceChanges>[0]} drops
   * @param {Parameters<typeof balanceChanges>[1]} settlements
   * @param {CommitOutcome} outcome
   */
  constructor (drops, settlements, outcome) {
    this.balances = new Map(outcome.balances)
    for (const [playerId, change] of balanceChanges(drops, settlements, outcome)) {
      const committed = this.balances.get(playerId)
      if (committed === undefined) throw new Error(`the ledger did not return the balance of ${playerId}`)
      this.balances.set(playerId, committed - change)
    }
  }

  /** Applies `amount` (negative for a bet) to a player's balance; returns the new balance. */
  apply (playerId, amount) {
    const before = this.balances.get(playerId)
    if (before === undefined) throw new Error(`the ledger did not return the balance of ${playerId}`)
    const balance = before + amount
    this.balances.set(playerId, balance)
    return balance
  }
}

/**
 * @typedef {object} CommitOutcome what a store's commitBatch returns
 * @property {Map<number, string>} rejected drop id → code of drops the ledger refused (nothing debited)
 * @property {Set<number>} settled ids of the drops this batch settled (and credited)
 * @property {Map<string, number>} balances every touched player's balance as committed
 */
