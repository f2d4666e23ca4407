/**
 * Credits paid for a bet at a multiplier. Multipliers have at most three
 * decimals; going through integer thousandths keeps 0.1 + 0.2 style float
 * error from costing a player a credit.
 * @param {number} bet integer credits @param {number} multiplier
 */
export function payoutFor (bet, multiplier) {
  return Math.floor(bet * Math.round(multiplier * 1000) / 1000)
}
