/**
 * Broad phase for static shapes, built once. Static geometry has known
 * bounds, so instead of hashing cells it uses a dense grid over those bounds
 * (the "or better" of a spatial hash: no collisions, no probing). Each shape
 * is stored in every cell where a moving circle of radius <= reach starting
 * in that cell could touch it, so a body needs exactly one cell lookup per
 * path. Each cell's shape ids ascend, so contacts are always met in
 * static-id order.
 */
export class StaticGrid {
  /**
   * @param {object} options
   * @param {number} options.cellSize
   */
  constructor ({ cellSize }) {
    this.cellSize = cellSize
    this.inverseCellSize = 1 / cellSize
    this._minX = 0
    this._minY = 0
    this._columns = 0
    this._rows = 0
    this.cellStart = new Int32Array(1)
    /** shape ids, grouped by cell */
    this.items = new Int32Array(0)
  }

  /**
   * Rebuilds the grid. `boundsOf(id, out)` writes shape `id`'s AABB grown by
   * the reach into out[0..3]; `touchesCell(id, minX, minY, maxX, maxY)`
   * answers whether the grown shape reaches that cell box.
   * @param {number} shapeCount
   * @param {(id: number, out: Float64Array) => void} boundsOf
   * @param {(id: number, minX: number, minY: number, maxX: number, maxY: number) => boolean} touchesCell
   */
  build (shapeCount, boundsOf, touchesCell) {
    const size = this.cellSize
    const inv = this.inverseCellSize
    const bounds = new Float64Array(4)
    const ranges = []
    let minX = Infinity; let minY = Infinity; let maxX = -Infinity; let maxY = -Infinity
    for (let id = 0; id < shapeCount; id++) {
      boundsOf(id, bounds)
      const range = [Math.floor(bounds[0] * inv), Math.floor(bounds[1] * inv), Math.floor(bounds[2] * inv), Math.floor(bounds[3] * inv)]
      ranges.push(range)
      minX = Math.min(minX, range[0]); minY = Math.min(minY, range[1])
      maxX = Math.max(maxX, range[2]); maxY = Math.max(maxY, range[3])
    }
    if (shapeCount === 0) { minX = minY = 0; maxX = maxY = -1 }
    this._minX = minX
    this._minY = minY
    this._columns = maxX - minX + 1
    this._rows = maxY - minY + 1
    const cells = this._columns * this._rows
    /** @type {number[][]} */
    const lists = Array.from({ length: cells }, () => [])
    for (let id = 0; id < shapeCount; id++) {
      const [x0, y0, x1, y1] = ranges[id]
      for (let iy = y0; iy <= y1; iy++) {
        for (let ix = x0; ix <= x1; ix++) {
          if (touchesCell(id, ix * size, iy * size, (ix + 1) * size, (iy + 1) * size)) {
            lists[(iy - minY) * this._columns + (ix - minX)].push(id)
          }
        }
      }
    }
    // Prefix offsets: cell c lists items[cellStart[c] .. cellStart[c + 1] - 1].
    let total = 0
    for (const list of lists) total += list.length
    // 16-bit offsets and ids when they fit (every board's do): half the bytes, so more of them stay cached.
    const Index = total <= 0xffff && shapeCount <= 0xffff ? Uint16Array : Int32Array
    this.cellStart = new Index(cells + 1)
    this.items = new Index(total)
    let offset = 0
    for (let cell = 0; cell < cells; cell++) {
      this.cellStart[cell] = offset
      for (const id of lists[cell]) this.items[offset++] = id
    }
    this.cellStart[cells] = offset
  }

  /**
   * Cell holding point (x, y), or -1 outside the grid. Its shapes are
   * items[cellStart[cell] .. cellStart[cell + 1] - 1]. A point within
   * rounding of a cell's edge may be placed in the cell beside it; shapes
   * are listed with a margin that covers that.
   * @param {number} x @param {number} y
   */
  cellAt (x, y) {
    const column = x * this.inverseCellSize - this._minX
    const row = y * this.inverseCellSize - this._minY
    // Compared as doubles, then truncated: `| 0` floors a non-negative value without a check.
    if (!(column >= 0 && row >= 0 && column < this._columns && row < this._rows)) return -1
    return (row | 0) * this._columns + (column | 0)
  }

  /** @param {number} cell */
  startOf (cell) { return this.cellStart[cell] }

  /** @param {number} cell */
  countOf (cell) { return this.cellStart[cell + 1] - this.cellStart[cell] }
}
