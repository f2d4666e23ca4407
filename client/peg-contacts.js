/**
 * Where a simulated ball touches pegs: read from the drop's own trajectory
 * (x, y, angle after every tick, from simulateDrop(…, { trajectory: true })),
 * so every glow and peg tick the page shows is one the simulation had.
 * A contact starts on the first tick the ball's centre is within
 * ballRadius + pegRadius (+ a little for the tick's discreteness) of a
 * peg's centre after a tick it was not.
 */

/** Extra reach beyond touching, in board px: a bounce can happen between two ticks. */
const CONTACT_SLACK = 0.25

/**
 * @typedef {object} PegContact
 * @property {number} tick ticks since release
 * @property {number} peg index in board.pegs
 * @property {number} row 0 = the top row
 */

/** @type {WeakMap<object, { cell: number, cols: number, rows: number, cells: Int32Array[], rowOf: Int32Array }>} */
const grids = new WeakMap()

/** The board's pegs in a grid of cells one peg spacing wide (built once per board). */
function gridOf (board) {
  let grid = grids.get(board)
  if (grid) return grid
  const cell = Math.max(1, 2 * (board.ballRadius + board.pegRadius + CONTACT_SLACK))
  const cols = Math.ceil(board.width / cell) + 1
  const rows = Math.ceil(board.height / cell) + 1
  const lists = Array.from({ length: cols * rows }, () => [])
  board.pegs.forEach((peg, i) => {
    const cx = Math.min(cols - 1, Math.max(0, Math.floor(peg.x / cell)))
    const cy = Math.min(rows - 1, Math.max(0, Math.floor(peg.y / cell)))
    lists[cy * cols + cx].push(i)
  })
  // Rows of pegs, top first, by their distinct heights.
  const heights = [...new Set(board.pegs.map((p) => p.y))].sort((a, b) => a - b)
  const rowOf = Int32Array.from(board.pegs, (p) => heights.indexOf(p.y))
  grid = { cell, cols, rows, cells: lists.map((list) => Int32Array.from(list)), rowOf }
  grids.set(board, grid)
  return grid
}

/**
 * The same rule one tick at a time, for a ball simulated as it is drawn
 * (seeds mode): at(tick, x, y) reports the contacts that start at that
 * tick. Allocates nothing per tick (a ball touches a handful of pegs at once).
 */
export class PegContactTracker {
  /** @param {import('/engine/board.js').Board} board */
  constructor (board) {
    this.board = board
    this._grid = gridOf(board)
    const reach = board.ballRadius + board.pegRadius + CONTACT_SLACK
    this._reach2 = reach * reach
    this._touching = new Int32Array(16)
    this._touchingCount = 0
    this._now = new Int32Array(16)
  }

  /** Forgets the pegs being touched (a new ball). */
  reset () {
    this._touchingCount = 0
    return this
  }

  /**
   * The ball's centre after tick `tick` is (x, y): pushes onto `out` a
   * contact for each peg it touches now and did not after the tick before.
   * @param {number} tick @param {number} x @param {number} y @param {PegContact[]} out
   */
  at (tick, x, y, out) {
    const grid = this._grid
    const pegs = this.board.pegs
    const cx = Math.floor(x / grid.cell)
    const cy = Math.floor(y / grid.cell)
    let count = 0
    for (let j = cy - 1; j <= cy + 1; j++) {
      if (j < 0 || j >= grid.rows) continue
      for (let i = cx - 1; i <= cx + 1; i++) {
        if (i < 0 || i >= grid.cols) continue
        const cell = grid.cells[j * grid.cols + i]
        for (let c = 0; c < cell.length; c++) {
          const peg = cell[c]
          const p = pegs[peg]
          const dx = p.x - x
          const dy = p.y - y
          if (dx * dx + dy * dy > this._reach2) continue
          if (count < this._now.length) this._now[count++] = peg
          if (!this._touches(peg)) out.push({ tick, peg, row: grid.rowOf[peg] })
        }
      }
    }
    const swap = this._touching
    this._touching = this._now
    this._now = swap
    this._touchingCount = count
  }

  _touches (peg) {
    for (let k = 0; k < this._touchingCount; k++) if (this._touching[k] === peg) return true
    return false
  }
}

/**
 * Every peg contact along a trajectory, in tick order.
 * @param {import('/engine/board.js').Board} board
 * @param {Float64Array} trajectory
 * @returns {PegContact[]}
 */
export function pegContacts (board, trajectory) {
  const tracker = new PegContactTracker(board)
  const contacts = []
  const ticks = trajectory.length / 3
  for (let t = 0; t < ticks; t++) tracker.at(t, trajectory[3 * t], trajectory[3 * t + 1], contacts)
  return contacts
}

/** Rows of pegs on `board`. @param {import('/engine/board.js').Board} board */
export function pegRowCount (board) {
  const grid = gridOf(board)
  let max = -1
  for (const row of grid.rowOf) if (row > max) max = row
  return max + 1
}
