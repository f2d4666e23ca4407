/**
 * Hash of an integer grid cell (Teschner et al. 2003, the primes of the
 * classic spatial hash), computed with 32-bit integer multiplies so every
 * engine agrees. Callers mask it to their table size.
 * @param {number} ix integer cell column
 * @param {number} iy integer cell row
 */
export function hashCell (ix, iy) {
  return Math.imul(ix, 73856093) ^ Math.imul(iy, 19349663)
}

/** Smallest power of two that is >= n (n >= 1). */
export function nextPowerOfTwo (n) {
  let p = 1
  while (p < n) p *= 2
  return p
}
