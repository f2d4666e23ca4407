/**
 * Whether an OPERATOR_TOKEN can survive guessing. The operator API is
 * throttled per address (limits/auth-failures.js), but many addresses
 * together still guess for as long as the server runs, and a token can
 * leak into a dictionary: a set token must be long and look random.
 * Its strength is estimated as length × the Shannon entropy of its
 * characters (what a guesser who knows its character frequencies faces):
 * 32 random bytes in hex, as `openssl rand -hex 32` makes them, give about
 * 250 bits; "passwordpassword" gives 44.
 */
export const MIN_OPERATOR_TOKEN_BITS = 80
export const MIN_DISTINCT_CHARACTERS = 10

/** Estimated bits of a token: length × entropy per character. @param {string} token */
export function estimatedBits (token) {
  const counts = new Map()
  for (const character of token) counts.set(character, (counts.get(character) ?? 0) + 1)
  const length = [...token].length
  let perCharacter = 0
  for (const count of counts.values()) perCharacter -= (count / length) * Math.log2(count / length)
  return length * perCharacter
}

/** Why the token is too weak, or null when it is strong enough. @param {string} token */
export function operatorTokenWeakness (token) {
  const distinct = new Set(token).size
  const bits = estimatedBits(token)
  if (distinct >= MIN_DISTINCT_CHARACTERS && bits >= MIN_OPERATOR_TOKEN_BITS) return null
  return `too weak to survive guessing (about ${Math.floor(bits)} bits from ${distinct} distinct characters; at least ${MIN_OPERATOR_TOKEN_BITS} bits and ${MIN_DISTINCT_CHARACTERS} distinct characters needed): use 32 random bytes in hex, e.g. \`openssl rand -hex 32\`, or leave it unset to generate one`
}
