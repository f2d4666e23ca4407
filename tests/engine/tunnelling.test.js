import { describe, it, expect } from 'vitest'
import { createHmac } from 'node:crypto'
import { createBoard } from '../../engine/board.js'
import { DropSimulator } from '../../engine/drop-simulator.js'
import { World } from '../../engine/world.js'
import { ENGINE_VERSIONS } from '../../engine/version.js'

// Signed distance of (x, y) from the infinite line through a wall, positive
// on the side of the board's centre.
function insideDistance (board, [x1, y1, x2, y2], x, y) {
  const ex = x2 - x1; const ey = y2 - y1
  const length = Math.sqrt(ex * ex + ey * ey)
  const side = (px, py) => ((px - x1) * ey - (py - y1) * ex) / length
  return side(x, y) * Math.sign(side(board.width / 2, y))
}

// The fastest a ball can go on a board: released at the top with the largest
// initial speed, falling the whole height without losing energy.
function maxReachableSpeed (board) {
  const { maxVx, maxVy } = board.release
  return Math.sqrt(maxVx * maxVx + maxVy * maxVy + 2 * board.solver.gravity * board.height)
}

describe.each(ENGINE_VERSIONS)('no tunnelling under engine %s', (engineVersion) => {
  const boardOf = (rows) => createBoard({ rows, risk: 'high', engineVersion })

  it('over 3,000 seeded drops, a ball never enters a peg and never leaves the walls', () => {
    let fastest = 0
    for (const rows of [8, 12, 16]) {
      const board = boardOf(rows)
      const simulator = new DropSimulator(board)
      const world = simulator.world
      const slanted = board.walls.filter(([x1, , x2]) => x1 !== x2)
      // Overlap between two checks: at most 2 px, or a quarter of the ball on small boards.
      const tolerance = Math.min(2, board.ballRadius / 4)
      const minPegGap = board.ballRadius + board.pegRadius - tolerance
      for (let n = 0; n < 1000; n++) {
        const body = simulator.addDrop(createHmac('sha256', 'tunnel').update(`${rows}:${n}`).digest('hex'))
        for (;;) {
          const x = world.xOf(body); const y = world.yOf(body)
          for (const peg of board.pegs) {
            const dx = x - peg.x; const dy = y - peg.y
            if (dx * dx + dy * dy < minPegGap * minPegGap) expect.fail(`drop ${rows}:${n} entered peg (${peg.x}, ${peg.y}) at tick ${simulator.ticksOf(body)}`)
          }
          for (const wall of slanted) {
            if (y >= Math.min(wall[1], wall[3]) && y <= Math.max(wall[1], wall[3])) {
              expect(insideDistance(board, wall, x, y)).toBeGreaterThan(board.ballRadius - tolerance)
            }
          }
          fastest = Math.max(fastest, Math.sqrt(world.vxOf(body) ** 2 + world.vyOf(body) ** 2))
          if (simulator.step().length > 0) break
          if (simulator.ticksOf(body) >= board.maxDropTicks - 1) expect.fail(`drop ${rows}:${n} did not land within ${board.maxDropTicks} ticks (wedged?)`)
        }
      }
    }
    expect(fastest).toBeLessThan(maxReachableSpeed(boardOf(16)))
  }, 120_000)

  it('a ball fired straight at any peg faster than any ball can fall bounces back', () => {
    const board = boardOf(16)
    const speed = maxReachableSpeed(board) * 1.5
    const travelPerTick = speed / 60
    // Every start phase within one tick's travel, so no lucky sampling hides a miss.
    for (let phase = 0; phase < travelPerTick; phase += 1.5) {
      for (const offset of [0, 0.5, 2, 4].map((o) => o * board.ballRadius / 7)) {
        for (const peg of board.pegs) {
        const world = new World({ maxBodyRadius: board.ballRadius })
        world.addStaticCircle(peg.x, peg.y, board.pegRadius, board.pegMaterial)
        const id = world.createCircle({ x: peg.x + offset, y: peg.y - 60 - phase, vy: speed, radius: board.ballRadius, material: board.ballMaterial })
        for (let i = 0; i < 12; i++) world.step()
        expect(world.vyOf(id)).toBeLessThan(0)
        expect(world.yOf(id)).toBeLessThan(peg.y)
        }
      }
    }
  })

  it('a ball fired square at a side wall faster than any ball can fall stays inside', () => {
    const board = boardOf(16)
    const speed = maxReachableSpeed(board) * 1.5
    for (const wall of board.walls.filter(([x1, , x2]) => x1 !== x2)) {
      const [x1, y1, x2, y2] = wall
      const ex = x2 - x1; const ey = y2 - y1
      const length = Math.sqrt(ex * ex + ey * ey)
      // Inward unit normal.
      let nx = -ey / length; let ny = ex / length
      if (insideDistance(board, wall, x1 + nx, y1 + ny) < 0) { nx = -nx; ny = -ny }
      for (const [t, phase] of [[0.1, 0], [0.3, 7], [0.5, 13], [0.7, 19], [0.9, 29]]) {
        const world = new World({ maxBodyRadius: board.ballRadius, gravityY: 0 })
        world.addStaticSegment(x1, y1, x2, y2, board.pegMaterial)
        const px = x1 + ex * t + nx * (40 + phase); const py = y1 + ey * t + ny * (40 + phase)
        const id = world.createCircle({ x: px, y: py, vx: -nx * speed, vy: -ny * speed, radius: board.ballRadius, material: board.ballMaterial })
        for (let i = 0; i < 20; i++) {
          world.step()
          expect(insideDistance(board, wall, world.xOf(id), world.yOf(id))).toBeGreaterThan(0)
        }
        expect(world.vxOf(id) * nx + world.vyOf(id) * ny).toBeGreaterThan(0) // moving away again
      }
    }
  })
})
