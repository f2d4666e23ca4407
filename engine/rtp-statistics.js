/**
 * Return to player from bucket counts: the mean multiplier per drop, its
 * standard error and a 95% confidence interval (normal approximation, which
 * is sound at the hundreds of thousands of drops calibration uses).
 * @param {ArrayLike<number>} counts drops per bucket
 * @param {ArrayLike<number>} multipliers per bucket
 */
export function rtpStatistics (counts, multipliers) {
  let drops = 0
  let sum = 0
  let sumSquares = 0
  for (let i = 0; i < counts.length; i++) {
    drops += counts[i]
    sum += counts[i] * multipliers[i]
    sumSquares += counts[i] * multipliers[i] * multipliers[i]
  }
  if (drops === 0) return { drops, rtp: NaN, standardError: NaN, ci95: [NaN, NaN] }
  const rtp = sum / drops
  const variance = Math.max(0, sumSquares / drops - rtp * rtp)
  const standardError = Math.sqrt(variance / drops)
  return { drops, rtp, standardError, ci95: [rtp - 1.96 * standardError, rtp + 1.96 * standardError] }
}
