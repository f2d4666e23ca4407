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
 * Every peg contact along a trajectory, in tick order.
 * @param {import('/engine/board.js').Board} board
 * @param {Float64Array} trajectory
 * @returns {PegContact[]}
 */
export function pegContacts (board, trajectory) {
  const grid = gridOf(board)
  const reach = board.ballRadius + board.pegRadius + CONTACT_SLACK
  const reach2 = reach * reach
  const touching = new Set()
  const contacts = []
  const ticks = trajectory.length / 3
  for (let t = 0; t < ticks; t++) {
    const x = trajectory[3 * t]
    const y = trajectory[3 * t + 1]
    const cx = Math.floor(x / grid.cell)
    const cy = Math.floor(y / grid.cell)
    const now = new Set()
    for (let j = cy - 1; j <= cy + 1; j++) {
      if (j < 0 || j >= grid.rows) continue
      for (let i = cx - 1; i <= cx + 1; i++) {
        if (i < 0 || i >= grid.cols) continue
        for (const peg of grid.cells[j * grid.cols + i]) {
          const p = board.pegs[peg]
          const dx = p.x - x
          const dy = p.y - y
          if (dx * dx + dy * dy > reach2) continue
          now.add(peg)
          if (!touching.has(peg)) contacts.push({ tick: t, peg, row: grid.rowOf[peg] })
        }
      }
    }
    touching.clear()
    for (const peg of now) touching.add(peg)
  }
  return contacts
}

/** Rows of pegs on `board`. @param {import('/engine/board.js').Board} board */
export function pegRowCount (board) {
  const grid = gridOf(board)
  let max = -1
  for (const row of grid.rowOf) if (row > max) max = row
  return max + 1
}
