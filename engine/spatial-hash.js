import { hashCell, nextPowerOfTwo } from './cell-hash.js'

/**
 * Broad phase for moving bodies, rebuilt every step without allocating:
 * bodies are counting-sorted into hash buckets by the cell of their centre
 * (in id order, so each bucket lists ids ascending). Cells are at least as
 * wide as the largest body, so two touching bodies are always in the same or
 * neighbouring cells. Pairs are visited in a fixed order: by the lower id,
 * then by neighbour cell, then by the higher id.
 */
export class SpatialHash {
  /**
   * @param {object} options
   * @param {number} options.cellSize
   * @param {number} options.capacity most bodies it will hold
   */
  constructor ({ cellSize, capacity }) {
    this.cellSize = cellSize
    this.inverseCellSize = 1 / cellSize
    this._resize(capacity)
    this._seen = new Int32Array(9)
  }

  _resize (capacity) {
    this.capacity = capacity
    const buckets = nextPowerOfTwo(Math.max(16, capacity * 2))
    this._mask = buckets - 1
    this._bucketStart = new Int32Array(buckets + 1)
    this._cursor = new Int32Array(buckets)
    this._entries = new Int32Array(capacity)
    this._bodyBucket = new Int32Array(capacity)
    this._cellX = new Int32Array(capacity)
    this._cellY = new Int32Array(capacity)
  }

  /**
   * @param {Float64Array} positions x of body i at i × stride, its y right after
   * @param {number} stride
   * @param {Uint8Array} member 1 for bodies to index
   * @param {number} count bodies 0..count-1 are considered
   */
  rebuild (positions, stride, member, count) {
    if (count > this.capacity) this._resize(nextPowerOfTwo(count))
    const start = this._bucketStart
    const cursor = this._cursor
    const inv = this.inverseCellSize
    start.fill(0)
    for (let i = 0; i < count; i++) {
      if (member[i] !== 1) { this._bodyBucket[i] = -1; continue }
      const ix = Math.floor(positions[i * stride] * inv)
      const iy = Math.floor(positions[i * stride + 1] * inv)
      const bucket = hashCell(ix, iy) & this._mask
      this._cellX[i] = ix
      this._cellY[i] = iy
      this._bodyBucket[i] = bucket
      start[bucket + 1]++
    }
    for (let b = 0; b <= this._mask; b++) {
      start[b + 1] += start[b]
      cursor[b] = start[b]
    }
    for (let i = 0; i < count; i++) {
      const bucket = this._bodyBucket[i]
      if (bucket >= 0) this._entries[cursor[bucket]++] = i
    }
  }

  /**
   * Calls visit(i, j) once for every indexed pair i < j whose centres lie in
   * the same or neighbouring cells (a superset of the touching pairs).
   * @param {number} count
   * @param {(i: number, j: number) => void} visit
   */
  forEachCandidatePair (count, visit) {
    const seen = this._seen
    const mask = this._mask
    const start = this._bucketStart
    const entries = this._entries
    for (let i = 0; i < count; i++) {
      if (this._bodyBucket[i] < 0) continue
      const cx = this._cellX[i]
      const cy = this._cellY[i]
      let seenCount = 0
      for (let dy = -1; dy <= 1; dy++) {
        for (let dx = -1; dx <= 1; dx++) {
          const bucket = hashCell(cx + dx, cy + dy) & mask
          let repeated = false
          for (let k = 0; k < seenCount; k++) if (seen[k] === bucket) { repeated = true; break }
          if (repeated) continue
          seen[seenCount++] = bucket
          for (let e = start[bucket], end = start[bucket + 1]; e < end; e++) {
            const j = entries[e]
            if (j <= i) continue
            // Hash collisions can bring far cells into the bucket: keep only
            // true neighbours so each pair is visited exactly once.
            const ddx = this._cellX[j] - cx
            const ddy = this._cellY[j] - cy
            if (ddx < -1 || ddx > 1 || ddy < -1 || ddy > 1) continue
            visit(i, j)
          }
        }
      }
    }
  }
}
