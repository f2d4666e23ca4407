import { describe, it, expect } from 'vitest'
import { createHmac } from 'node:crypto'
import { World } from '../../engine/world.js'
import { createBoard } from '../../engine/board.js'
import { DropSimulator } from '../../engine/drop-simulator.js'
import { dropInitialConditions } from '../../engine/drop-initial-conditions.js'
import { HARD_PLASTIC } from '../../engine/materials.js'

const seed = (n) => createHmac('sha256', 'shared-statics-test').update(String(n)).digest('hex')

/** A world with its own copy of the board's pegs and walls, built the way DropSimulator's shared one is. */
function ownWorld (board) {
  const world = new World({ maxBodyRadius: board.ballRadius, staticCellSize: 16 })
  for (const peg of board.pegs) world.addStaticCircle(peg.x, peg.y, board.pegRadius, board.pegMaterial)
  for (const [x1, y1, x2, y2] of board.walls) world.addStaticSegment(x1, y1, x2, y2, board.pegMaterial)
  return world
}

function release (world, board, n) {
  return world.createCircle({ ...dropInitialConditions(board, seed(n)), radius: board.ballRadius, material: board.ballMaterial, collidesWithBodies: false })
}

describe('worlds sharing static shapes (sharedStatics)', () => {
  it('step exactly as a world with its own copy of the shapes', () => {
    const board = createBoard({ rows: 12, risk: 'low' })
    const own = ownWorld(board)
    const template = ownWorld(board)
    const sharing = [new World({ maxBodyRadius: board.ballRadius, sharedStatics: template }), new World({ maxBodyRadius: board.ballRadius, sharedStatics: template })]
    for (let n = 0; n < 30; n++) {
      release(own, board, n)
      for (const world of sharing) release(world, board, n)
    }
    for (let tick = 0; tick < 400; tick++) {
      own.step()
      for (const world of sharing) world.step()
      if (tick % 50 === 0) for (const world of sharing) expect(world.stateHash()).toBe(own.stateHash())
    }
    for (const world of sharing) expect(world.stateHash()).toBe(own.stateHash())
    expect(sharing[0].statics).toBe(template.statics)
  })

  it('DropSimulators on one board share one copy', () => {
    const board = createBoard({ rows: 9, risk: 'high' })
    const a = new DropSimulator(board)
    const b = new DropSimulator(board)
    expect(a.world.staticGrid).toBe(b.world.staticGrid)
    expect(a.world.statics.count).toBe(board.pegs.length + board.walls.length)
    expect(new DropSimulator(createBoard({ rows: 9, risk: 'high' })).world.staticGrid).not.toBe(a.world.staticGrid)
  })

  it('refuses to change shared shapes, from either side, and a mismatched source', () => {
    const board = createBoard({ rows: 8, risk: 'low' })
    const template = ownWorld(board)
    const world = new World({ maxBodyRadius: board.ballRadius, sharedStatics: template })
    expect(() => world.addStaticCircle(0, 0, 3, HARD_PLASTIC)).toThrow(/shared/)
    expect(() => template.addStaticSegment(0, 0, 10, 0, HARD_PLASTIC)).toThrow(/shared/)
    expect(template.statics.count).toBe(board.pegs.length + board.walls.length)
    expect(() => new World({ maxBodyRadius: board.ballRadius + 1, sharedStatics: template })).toThrow(RangeError)
    expect(() => new World({ sharedStatics: {} })).toThrow(TypeError)
  })
})
