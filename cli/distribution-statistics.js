/**
 * How a board's bucket distribution compares with an ideal Galton board,
 * where every peg sends the ball left or right with probability ½:
 * Binomial(rows, ½) over the rows + 1 buckets.
 */

/** Binomial(rows, ½) probabilities of buckets 0..rows. @param {number} rows @returns {number[]} */
export function binomialDistribution (rows) {
  let p = [1]
  for (let r = 0; r < rows; r++) {
    const next = new Array(p.length + 1).fill(0)
    for (let k = 0; k < p.length; k++) { next[k] += p[k] / 2; next[k + 1] += p[k] / 2 }
    p = next
  }
  return p
}

/** Total-variation distance between bucket counts and a distribution: ½ Σ |count/n − p|. @param {ArrayLike<number>} counts @param {number[]} p */
export function totalVariation (counts, p) {
  let n = 0
  for (let i = 0; i < counts.length; i++) n += counts[i]
  let sum = 0
  for (let i = 0; i < p.length; i++) sum += Math.abs(counts[i] / n - p[i])
  return sum / 2
}

/**
 * Share of drops in the `k` outermost buckets on either side, over the
 * binomial's share: above 1 the board's tails are fatter than a Galton
 * board's (balls fly across rows), below 1 thinner.
 * @param {ArrayLike<number>} counts @param {number} [k]
 */
export function tailRatio (counts, k = 3) {
  const rows = counts.length - 1
  const p = binomialDistribution(rows)
  let n = 0
  for (let i = 0; i < counts.length; i++) n += counts[i]
  let measured = 0
  let ideal = 0
  for (let i = 0; i < k; i++) { measured += counts[i] + counts[rows - i]; ideal += p[i] + p[rows - i] }
  return measured / n / ideal
}

/** Probability of one edge bucket (the two averaged: the board is symmetric). @param {ArrayLike<number>} counts */
export function edgeProbability (counts) {
  let n = 0
  for (let i = 0; i < counts.length; i++) n += counts[i]
  return (counts[0] + counts[counts.length - 1]) / 2 / n
}
