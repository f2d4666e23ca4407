import seedrandom from 'seedrandom'

/**
 * The drop's pseudo-random stream: seedrandom's ARC4 generator keyed by the
 * drop seed string. It is pure integer arithmetic (RC4 with exact
 * power-of-two scaling), so every JavaScript engine yields the same doubles.
 * @param {string} seed
 * @returns {() => number} uniform doubles in [0, 1)
 */
export function createRandom (seed) {
  return seedrandom(seed)
}
