/**
 * The plain closing line a CI log reader takes as a run's count whatever
 * runner it knows: `Label: N passed, N failed` (`, N skipped` when any were),
 * alone on its line. One copy, used by the vitest reporter and the fuzzer's
 * output filter.
 * @param {string} label one word, no spaces
 * @param {{ passed: number, failed: number, skipped: number }} counts
 */
export function closingLine (label, { passed, failed, skipped }) {
  return `${label}: ${passed} passed, ${failed} failed` + (skipped > 0 ? `, ${skipped} skipped` : '')
}
