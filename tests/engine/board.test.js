import { describe, it, expect } from 'vitest'
import { createBoard, bucketAt, MIN_ROWS, MAX_ROWS, RISKS } from '../../engine/board.js'
import { ENGINE_VERSION, ENGINE_VERSIONS, engineRules } from '../../engine/version.js'

describe.each(ENGINE_VERSIONS)('createBoard under engine %s', (engineVersion) => {
  const rules = engineRules(engineVersion)

  it('builds every rows × risk board: a triangle of pegs, rows + 1 buckets, a multiplier each', () => {
    for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
      for (const risk of RISKS) {
        const board = createBoard({ rows, risk, engineVersion })
        expect(board.engineVersion).toBe(engineVersion)
        expect(board.pegs.length).toBe((rows * (rows + 5)) / 2) // sum of r + 3 for r < rows
        expect(board.multipliers).toEqual([...rules.multipliers[rows][risk]])
        expect(board.multipliers.length).toBe(rows + 1)
        expect(board.multipliers).toEqual([...board.multipliers].reverse()) // symmetric
        // Never decreasing from the centre outwards.
        for (let i = 0; i < rows / 2; i++) expect(board.multipliers[i]).toBeGreaterThanOrEqual(board.multipliers[i + 1])
        // Row r has r + 3 pegs, centred.
        const firstRow = board.pegs.filter((p) => p.y === board.pegs[0].y)
        expect(firstRow.length).toBe(3)
        expect(firstRow[1].x).toBe(board.width / 2)
        const lastY = board.pegs[board.pegs.length - 1].y
        const lastRow = board.pegs.filter((p) => p.y === lastY)
        expect(lastRow.length).toBe(rows + 2)
        expect(board.bucketLeftX).toBeCloseTo(lastRow[0].x, 9)
        expect(board.bucketLeftX + (rows + 1) * board.bucketWidth).toBeCloseTo(lastRow[lastRow.length - 1].x, 9)
        expect(board.bucketLineY).toBeGreaterThan(lastY)
        expect(board.dropZone.minX).toBeLessThan(board.dropZone.maxX)
        expect(JSON.parse(JSON.stringify(board))).toEqual(board) // plain data, sent to clients
      }
    }
  })

  it('leaves the ball room to pass between two pegs (it can never wedge there)', () => {
    const board = createBoard({ rows: 16, risk: 'low', engineVersion })
    expect(2 * board.ballRadius).toBeLessThan(board.bucketWidth - 2 * board.pegRadius)
  })

  it('puts the slanted walls tangent to the outermost pegs, so no ball can sit between them', () => {
    const board = createBoard({ rows: 12, risk: 'low', engineVersion })
    const [x1, y1, x2, y2] = board.walls.find(([a, , c]) => a !== c)
    const length = Math.sqrt((x2 - x1) ** 2 + (y2 - y1) ** 2)
    const distance = (p) => Math.abs((p.x - x1) * (y2 - y1) - (p.y - y1) * (x2 - x1)) / length
    const outerLeft = board.pegs.filter((p, i, all) => !all.some((q) => q.y === p.y && q.x < p.x))
    for (const peg of outerLeft) expect(distance(peg)).toBeCloseTo(board.pegRadius, 9)
  })

  it('maps x to buckets and clamps outside the last row', () => {
    const board = createBoard({ rows: 8, risk: 'medium', engineVersion })
    expect(bucketAt(board, board.bucketLeftX - 50)).toBe(0)
    expect(bucketAt(board, board.bucketLeftX + 0.5 * board.bucketWidth)).toBe(0)
    expect(bucketAt(board, board.bucketLeftX + 3.5 * board.bucketWidth)).toBe(3)
    expect(bucketAt(board, board.bucketLeftX + 100 * board.bucketWidth)).toBe(8)
  })
})

describe('createBoard', () => {
  it('builds the newest version by default', () => {
    expect(createBoard({ rows: 8, risk: 'low' }).engineVersion).toBe(ENGINE_VERSION)
    expect(ENGINE_VERSIONS[ENGINE_VERSIONS.length - 1]).toBe(ENGINE_VERSION)
  })

  it('rejects bad options with a clear error', () => {
    expect(() => createBoard({ rows: 7, risk: 'low' })).toThrow(/rows must be an integer from 8 to 16/)
    expect(() => createBoard({ rows: 17, risk: 'low' })).toThrow(RangeError)
    expect(() => createBoard({ rows: 12.5, risk: 'low' })).toThrow(RangeError)
    expect(() => createBoard({ rows: 12, risk: 'extreme' })).toThrow(/risk must be one of low, medium, high/)
    expect(() => createBoard()).toThrow(RangeError)
  })
})
