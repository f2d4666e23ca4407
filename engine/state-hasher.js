/**
 * Hashes the exact IEEE-754 bits of doubles (and small integers) into 64 bits
 * made of two independent 32-bit murmur3-style lanes. Only integer ops
 * (Math.imul, shifts, xor) are used, so every JavaScript engine gives the
 * same digest. One hasher is reused: adding values allocates nothing.
 */
export class StateHasher {
  constructor () {
    this._bytes = new ArrayBuffer(8)
    this._view = new DataView(this._bytes)
    this.reset()
  }

  reset () {
    this._h1 = 0x811c9dc5 | 0
    this._h2 = 0x1b873593 | 0
    this._length = 0
    return this
  }

  /** @param {number} word a 32-bit integer */
  addInt32 (word) {
    let k = Math.imul(word | 0, 0xcc9e2d51)
    k = (k << 15) | (k >>> 17)
    k = Math.imul(k, 0x1b873593)
    let h1 = this._h1 ^ k
    h1 = (h1 << 13) | (h1 >>> 19)
    this._h1 = (Math.imul(h1, 5) + 0xe6546b64) | 0

    let m = Math.imul(word | 0, 0x85ebca6b)
    m = (m << 13) | (m >>> 19)
    m = Math.imul(m, 0xc2b2ae35)
    let h2 = this._h2 ^ m
    h2 = (h2 << 17) | (h2 >>> 15)
    this._h2 = (Math.imul(h2, 9) + 0x27d4eb2f) | 0
    this._length++
    return this
  }

  /** @param {number} value any double; its bits are hashed, little-endian words */
  addFloat64 (value) {
    this._view.setFloat64(0, value, true)
    this.addInt32(this._view.getInt32(0, true))
    this.addInt32(this._view.getInt32(4, true))
    return this
  }

  /** @returns {string} 16 lowercase hex digits */
  digestHex () {
    const h1 = finalMix(this._h1 ^ this._length)
    const h2 = finalMix(this._h2 ^ this._length ^ h1)
    return hex32(h1) + hex32(h2)
  }
}

function finalMix (h) {
  h ^= h >>> 16
  h = Math.imul(h, 0x85ebca6b)
  h ^= h >>> 13
  h = Math.imul(h, 0xc2b2ae35)
  h ^= h >>> 16
  return h >>> 0
}

function hex32 (n) {
  return (n >>> 0).toString(16).padStart(8, '0')
}
