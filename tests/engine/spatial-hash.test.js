import { describe, it, expect } from 'vitest'
import seedrandom from 'seedrandom'
import { SpatialHash } from '../../engine/spatial-hash.js'
import { StaticGrid } from '../../engine/static-grid.js'
import { StaticShapes } from '../../engine/static-shapes.js'
import { World } from '../../engine/world.js'
import { DropSimulator } from '../../engine/drop-simulator.js'
import { createBoard, MIN_ROWS, MAX_ROWS, RISKS } from '../../engine/board.js'
import { ENGINE_VERSIONS } from '../../engine/version.js'

function randomBodies (count, seed, spread) {
  const random = seedrandom(seed)
  const xs = new Float64Array(count)
  const ys = new Float64Array(count)
  const radii = new Float64Array(count)
  const member = new Uint8Array(count)
  for (let i = 0; i < count; i++) {
    xs[i] = (random() - 0.5) * spread
    ys[i] = (random() - 0.5) * spread
    radii[i] = 2 + random() * 10
    member[i] = random() < 0.9 ? 1 : 0
  }
  // Interleaved as in World.state: x then y, every `stride` doubles.
  const stride = 3
  const positions = new Float64Array(count * stride)
  for (let i = 0; i < count; i++) { positions[i * stride] = xs[i]; positions[i * stride + 1] = ys[i] }
  return { xs, ys, radii, member, positions, stride }
}

function touchingPairsBruteForce ({ xs, ys, radii, member }) {
  const pairs = []
  for (let i = 0; i < xs.length; i++) {
    for (let j = i + 1; j < xs.length; j++) {
      if (!member[i] || !member[j]) continue
      const dx = xs[i] - xs[j]; const dy = ys[i] - ys[j]; const r = radii[i] + radii[j]
      if (dx * dx + dy * dy < r * r) pairs.push(`${i}-${j}`)
    }
  }
  return pairs
}

describe('SpatialHash (dynamic broad phase)', () => {
  for (const [count, spread, seed] of [[200, 400, 'a'], [1000, 1500, 'b'], [500, 100, 'dense'], [300, 1e6, 'sparse']]) {
    it(`finds exactly the brute-force touching pairs (${count} bodies over ${spread} px)`, () => {
      const bodies = randomBodies(count, seed, spread)
      const hash = new SpatialHash({ cellSize: 25, capacity: 16 })
      hash.rebuild(bodies.positions, bodies.stride, bodies.member, count)
      const seen = new Set()
      const found = []
      hash.forEachCandidatePair(count, (i, j) => {
        expect(i).toBeLessThan(j)
        const key = `${i}-${j}`
        expect(seen.has(key)).toBe(false) // each pair visited once
        seen.add(key)
        const dx = bodies.xs[i] - bodies.xs[j]; const dy = bodies.ys[i] - bodies.ys[j]; const r = bodies.radii[i] + bodies.radii[j]
        if (dx * dx + dy * dy < r * r) found.push(key)
      })
      expect(found.sort()).toEqual(touchingPairsBruteForce(bodies).sort())
    })
  }

  it('visits pairs in the same order on every rebuild', () => {
    const bodies = randomBodies(300, 'order', 300)
    const hash = new SpatialHash({ cellSize: 25, capacity: 300 })
    const run = () => {
      hash.rebuild(bodies.positions, bodies.stride, bodies.member, 300)
      const order = []
      hash.forEachCandidatePair(300, (i, j) => order.push(i * 1000 + j))
      return order
    }
    expect(run()).toEqual(run())
  })
})

describe('StaticGrid (static broad phase)', () => {
  /** Whether, at random points, the grid lists every shape a body of maxRadius there could touch. Returns the touches checked. */
  function expectEveryTouchListed (grid, shapes, maxRadius, random, points = 5000) {
    let checked = 0
    for (let n = 0; n < points; n++) {
      const x = -20 + random() * 640
      const y = -20 + random() * 640
      const listed = new Set()
      const slot = grid.cellAt(x, y)
      if (slot >= 0) for (let k = grid.startOf(slot); k < grid.startOf(slot) + grid.countOf(slot); k++) listed.add(grid.items[k])
      for (let id = 0; id < shapes.count; id++) {
        if (shapes.distanceSquaredTo(id, x, y) <= maxRadius * maxRadius) {
          expect(listed.has(id)).toBe(true)
          checked++
        }
      }
    }
    return checked
  }

  it('lists, for any point, every static shape a body of the largest radius there could touch', () => {
    const shapes = new StaticShapes()
    const random = seedrandom('statics')
    const material = { restitution: 0.5, friction: 0.3 }
    for (let i = 0; i < 150; i++) shapes.addCircle(random() * 600, random() * 600, 2 + random() * 6, material)
    for (let i = 0; i < 20; i++) shapes.addSegment(random() * 600, random() * 600, random() * 600, random() * 600, material)
    for (let i = 0; i < 10; i++) { const x = random() * 550; const y = random() * 550; shapes.addBox(x, y, x + 5 + random() * 40, y + 5 + random() * 40, material) }
    const maxRadius = 7
    const grid = new StaticGrid({ cellSize: 32 })
    grid.build(shapes.count, (id, out) => shapes.boundsOf(id, maxRadius, out), (id, a, b, c, d) => shapes.nearBox(id, maxRadius, a, b, c, d))
    expect(expectEveryTouchListed(grid, shapes, maxRadius, random)).toBeGreaterThan(500)
  })

  it('keeps its offsets and ids in 16 bits where they fit (every board), in 32 bits beyond', () => {
    for (const engineVersion of ENGINE_VERSIONS) {
      for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
        const grid = new DropSimulator(createBoard({ rows, risk: RISKS[rows % RISKS.length], engineVersion })).world.staticGrid
        expect(grid.items).toBeInstanceOf(Uint16Array)
        expect(grid.cellStart).toBeInstanceOf(Uint16Array)
      }
    }
    // Small cells and wide shapes: each shape is listed in thousands of cells.
    const shapes = new StaticShapes()
    const random = seedrandom('statics, many items')
    const material = { restitution: 0.5, friction: 0.3 }
    for (let i = 0; i < 120; i++) shapes.addCircle(random() * 600, random() * 600, 4 + random() * 12, material)
    for (let i = 0; i < 10; i++) shapes.addSegment(random() * 600, random() * 600, random() * 600, random() * 600, material)
    const maxRadius = 8
    const grid = new StaticGrid({ cellSize: 1 })
    grid.build(shapes.count, (id, out) => shapes.boundsOf(id, maxRadius, out), (id, a, b, c, d) => shapes.nearBox(id, maxRadius, a, b, c, d))
    expect(grid.items.length).toBeGreaterThan(0xffff)
    expect(grid.items).toBeInstanceOf(Int32Array)
    expect(grid.cellStart).toBeInstanceOf(Int32Array)
    expect(expectEveryTouchListed(grid, shapes, maxRadius, random, 2000)).toBeGreaterThan(100)
  })

  it('keeps shape ids ascending within each cell (contacts solved in a fixed order)', () => {
    const world = new World()
    for (let i = 0; i < 100; i++) world.addStaticCircle((i * 37) % 300, (i * 53) % 300, 4, { restitution: 0.5, friction: 0.3 })
    world.step()
    const grid = world.staticGrid
    for (let y = 0; y < 300; y += 10) {
      for (let x = 0; x < 300; x += 10) {
        const slot = grid.cellAt(x, y)
        if (slot < 0) continue
        for (let k = grid.startOf(slot) + 1; k < grid.startOf(slot) + grid.countOf(slot); k++) {
          expect(grid.items[k]).toBeGreaterThan(grid.items[k - 1])
        }
      }
    }
  })
})
