/**
 * How a landing pays, shared by the server (which pays) and the pages
 * (which check it). Money in the ledger is integer milli-credits; a bet is
 * a whole number of credits; a multiplier has at most three decimals.
 *
 * Each drop records the rule it was paid under, so an audit recomputes an
 * old drop's payout exactly as it was made, forever:
 *   1  legacy (ledgers before migration 2): floor(bet × multiplier) credits,
 *      which cost a 1-credit bet up to half its return
 *   2  exact: bet × multiplier in milli-credits, no rounding at all
 */

export const MILLI_PER_CREDIT = 1000

export const PAYOUT_RULES = Object.freeze([1, 2])

/** The rule new drops are paid under. */
export const PAYOUT_RULE = 2

/**
 * The payout, in milli-credits, of a bet at a multiplier under a rule.
 * Going through integer thousandths of the multiplier keeps float error out.
 * @param {number} bet whole credits @param {number} multiplier @param {number} [rule]
 */
export function payoutMilli (bet, multiplier, rule = PAYOUT_RULE) {
  const thousandths = Math.round(multiplier * 1000)
  if (rule === 2) return bet * thousandths
  if (rule === 1) return Math.floor(bet * thousandths / 1000) * MILLI_PER_CREDIT
  throw new RangeError(`no payout rule ${rule}`)
}

/** Milli-credits as credits (a number with at most three decimals). @param {number} milli */
export function toCredits (milli) {
  return milli / MILLI_PER_CREDIT
}

/** Whole or fractional credits (at most three decimals) as milli-credits. @param {number} credits */
export function toMilli (credits) {
  return Math.round(credits * MILLI_PER_CREDIT)
}
