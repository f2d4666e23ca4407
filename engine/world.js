import { StaticShapes, SHAPE_CIRCLE, PARAMS_PER_SHAPE, SWEEP_DX, SWEEP_DY, SWEEP_TIME, SWEEP_NX, SWEEP_NY, SWEEP_DEPTH, SWEEP_SIZE } from './static-shapes.js'
import { StaticGrid } from './static-grid.js'
import { SpatialHash } from './spatial-hash.js'
import { solveStaticContact, solveBodyContact } from './contact-solver.js'
import { FixedTimestep } from './fixed-timestep.js'
import { StateHasher } from './state-hasher.js'
import { METAL } from './materials.js'
import {
  BODY_STRIDE, BODY_X, BODY_Y, BODY_VX, BODY_VY, BODY_ANGLE, BODY_SPIN, BODY_PREVIOUS_X, BODY_PREVIOUS_Y,
  BODY_PREVIOUS_ANGLE, BODY_RADIUS, BODY_INVERSE_MASS, BODY_INVERSE_INERTIA, BODY_RESTITUTION, BODY_FRICTION, BODY_ALIVE
} from './body-layout.js'

export const DEFAULT_TIMESTEP = 1 / 60
export const DEFAULT_GRAVITY = 980
export const DEFAULT_CELL_SIZE = 50
/** A body never moves more than this fraction of its radius in one sub-step, so its centre can never cross a wall or a peg unseen. */
export const MAX_TRAVEL_PER_SUBSTEP = 1
export const MAX_SUBSTEPS = 16
/** Impacts resolved per sub-step; a ball wedged in a corner stops there for the rest of it. */
export const MAX_IMPACTS_PER_SUBSTEP = 4
const TWO_PI = 6.283185307179586
// The body layout as module-private constants, which V8 folds into the code (see body-layout.js).
const STRIDE = BODY_STRIDE
const X = BODY_X; const Y = BODY_Y; const VX = BODY_VX; const VY = BODY_VY
const ANGLE = BODY_ANGLE; const SPIN = BODY_SPIN
const PREVIOUS_X = BODY_PREVIOUS_X; const PREVIOUS_Y = BODY_PREVIOUS_Y; const PREVIOUS_ANGLE = BODY_PREVIOUS_ANGLE
const RADIUS = BODY_RADIUS; const INVERSE_MASS = BODY_INVERSE_MASS; const INVERSE_INERTIA = BODY_INVERSE_INERTIA
const RESTITUTION = BODY_RESTITUTION; const FRICTION = BODY_FRICTION; const ALIVE = BODY_ALIVE
/** Floats per static shape in World._gridRecords: peg x, y, radius (-1: not a peg). */
const GRID_RECORD = 3
/** px: far above the rounding error of board coordinates, far below any distance that matters. */
const SLAB_TOLERANCE = 1e-6

/**
 * Whether a circle's straight path certainly misses a peg, from
 * b = m·d, c = |m|² - reach² and a = |d|² (m: offset from the peg, d: the
 * path). The squared distance along the path is f(t) = a·t² + 2b·t + c; a
 * hit needs f ≤ 0 for some t in [0, 1] while approaching (b < 0). Bitwise,
 * not short-circuit: its parts are cheap, a mispredicted branch is not.
 */
function pegPathMisses (b, c, pathLength2) {
  return (b >= 0) | ((c > 0) & (pathLength2 + 2 * b + c > 0) & ((-b >= pathLength2) | (b * b < pathLength2 * c)))
}

/**
 * Whether a circle's straight path certainly misses a segment: its signed
 * distance to the segment's line stays beyond `slab` (its radius plus
 * SLAB_TOLERANCE, which keeps the test conservative against rounding) on
 * one side from start to end, so no part of the segment can be touched.
 */
function segmentPathMisses (sideStart, sideEnd, slab) {
  return ((sideStart > slab) & (sideEnd > slab)) | ((sideStart < -slab) & (sideEnd < -slab))
}

/**
 * A 2D rigid-body world of dynamic circles and static shapes.
 *
 * Per-body state lives in one Float64Array, `state`, a block of
 * BODY_STRIDE doubles per body id (body-layout.js; read it with xOf(id),
 * yOf(id), angleOf(id) …); every loop runs in id order, so results never
 * depend on insertion into a hash table.
 * Each step integrates with semi-implicit Euler (velocity first, then
 * position with the new velocity). The position update is a straight path
 * swept against the static shapes: the body stops at the first time of
 * impact, the impulse is applied there, and it carries on with the new
 * velocity, so it never sinks into a peg or passes through a wall. A fast
 * body is split into sub-steps of at most one radius of travel. The split is
 * decided per body from its own speed, so bodies that do not collide with
 * each other evolve independently: a ball's path is the same alone or among
 * a hundred others. Body-body contacts (when enabled) are resolved once per
 * step, after the motion, through the spatial hash.
 */
export class World {
  /**
   * @param {object} [options]
   * @param {number} [options.gravityX] px/s²
   * @param {number} [options.gravityY] px/s², default 980 (down)
   * @param {number} [options.timestep] s, default 1/60
   * @param {number} [options.cellSize] spatial hash cell (px), default 50
   * @param {number} [options.maxBodyRadius] largest dynamic radius allowed, default cellSize / 2
   * @param {number} [options.maxStepsPerUpdate] cap on steps per update() call
   * @param {number} [options.capacity] initial body capacity
   * @param {World} [options.sharedStatics] a world whose static shapes (and
   *   their grid) this one uses, read-only, instead of holding its own: many
   *   worlds on one board then share one copy, which stays in the CPU's cache.
   *   Its maxBodyRadius and staticCellSize must cover this world's; neither
   *   world may add static shapes afterwards.
   */
  constructor (options = {}) {
    this.gravityX = options.gravityX ?? 0
    this.gravityY = options.gravityY ?? DEFAULT_GRAVITY
    this.timestep = options.timestep ?? DEFAULT_TIMESTEP
    this.cellSize = options.cellSize ?? DEFAULT_CELL_SIZE
    this.maxBodyRadius = options.maxBodyRadius ?? this.cellSize / 2
    if (!(this.maxBodyRadius * 2 <= this.cellSize)) throw new RangeError('cellSize must be at least twice maxBodyRadius')
    this.clock = new FixedTimestep({ timestep: this.timestep, maxSteps: options.maxStepsPerUpdate ?? 5 })
    const shared = options.sharedStatics
    if (shared) {
      if (!(shared instanceof World)) throw new TypeError('sharedStatics must be a World')
      if (!(shared.maxBodyRadius >= this.maxBodyRadius)) throw new RangeError('sharedStatics must allow bodies at least as large (maxBodyRadius)')
      if (shared._staticsDirty) shared._rebuildStaticGrid()
      shared._staticsLocked = true
      this.statics = shared.statics
      this.staticGrid = shared.staticGrid
      this._gridRecords = shared._gridRecords
    } else {
      this.statics = new StaticShapes()
      this.staticGrid = new StaticGrid({ cellSize: options.staticCellSize ?? this.cellSize })
      this._gridRecords = new Float64Array(0)
    }
    this._staticsDirty = false
    /** true when the static shapes are shared with other worlds, so they cannot change */
    this._staticsLocked = Boolean(shared)
    this.tick = 0
    this.bodyCount = 0 // ids 0..bodyCount-1 have been used
    this._freeCount = 0 // _freeIds[0.._freeCount-1]: ids of destroyed bodies, descending
    this._allocate(options.capacity ?? 64)
    this._pairHash = new SpatialHash({ cellSize: this.cellSize, capacity: this.capacity })
    this._pairCount = 0 // live bodies that collide with other bodies
    this._contact = new Float64Array(SWEEP_SIZE)
    this._sweep = new Float64Array(SWEEP_SIZE)
    this._pairContact = new Float64Array(3)
    this._hasher = new StateHasher()
    this._solvePair = (i, j) => this._collidePair(i, j)
  }

  _allocate (capacity) {
    const old = this.capacity ? this : null
    this.capacity = capacity
    /** Every body's state, BODY_STRIDE doubles per id (body-layout.js); read it with xOf(id) and the others. */
    const state = new Float64Array(capacity * STRIDE)
    if (old) state.set(old.state)
    this.state = state
    const u8 = (name) => { const a = new Uint8Array(capacity); if (old) a.set(old[name]); return a }
    this.collidesWithBodies = u8('collidesWithBodies')
    /** bodies the fast loop of _advanceBodies() hands to its full swept path this step */
    this._handedOver = new Int32Array(capacity)
    const i32 = (name) => { const a = new Int32Array(capacity); if (old) a.set(old[name]); return a }
    this._freeIds = i32('_freeIds')
  }

  // ---- reading a body ----------------------------------------------------

  /** @param {number} id */ xOf (id) { return this.state[id * STRIDE + X] }
  /** @param {number} id */ yOf (id) { return this.state[id * STRIDE + Y] }
  /** @param {number} id */ vxOf (id) { return this.state[id * STRIDE + VX] }
  /** @param {number} id */ vyOf (id) { return this.state[id * STRIDE + VY] }
  /** @param {number} id radians, in [0, 2π) */ angleOf (id) { return this.state[id * STRIDE + ANGLE] }
  /** @param {number} id rad/s */ angularVelocityOf (id) { return this.state[id * STRIDE + SPIN] }
  /** @param {number} id */ radiusOf (id) { return this.state[id * STRIDE + RADIUS] }
  /** @param {number} id 1 / mass */ inverseMassOf (id) { return this.state[id * STRIDE + INVERSE_MASS] }
  /** @param {number} id pose before the last step */ previousXOf (id) { return this.state[id * STRIDE + PREVIOUS_X] }
  /** @param {number} id */ previousYOf (id) { return this.state[id * STRIDE + PREVIOUS_Y] }

  // ---- static geometry -------------------------------------------------

  addStaticCircle (x, y, radius, material) { this._changeStatics(); return this.statics.addCircle(x, y, radius, material) }
  addStaticSegment (x1, y1, x2, y2, material) { this._changeStatics(); return this.statics.addSegment(x1, y1, x2, y2, material) }
  // Kept though no board uses boxes: the engine is a general 2D rigid-body engine (docs/engine.md), and
  // the broad-phase and sweep tests exercise every shape kind against brute force.
  addStaticBox (minX, minY, maxX, maxY, material) { this._changeStatics(); return this.statics.addBox(minX, minY, maxX, maxY, material) }

  _changeStatics () {
    if (this._staticsLocked) throw new Error('static shapes are shared with another world (sharedStatics) and cannot change')
    this._staticsDirty = true
  }

  _rebuildStaticGrid () {
    // A body looks up the cell where its sub-step path starts; the path is at
    // most one radius long, so list every shape within two radii of a cell.
    const margin = this.maxBodyRadius * (1 + MAX_TRAVEL_PER_SUBSTEP)
    const statics = this.statics
    this.staticGrid.build(
      statics.count,
      (id, out) => statics.boundsOf(id, margin, out),
      (id, minX, minY, maxX, maxY) => statics.nearBox(id, margin, minX, minY, maxX, maxY)
    )
    this._staticsDirty = false
    // Each shape's peg centre and radius in one small record, read through
    // the grid's items: a board's records stay a few KiB (one per shape, not
    // one per cell a shape is listed in), so they stay in the CPU's cache
    // while other boards and the server's work pass through it; radius -1
    // marks a segment, which goes through StaticShapes.sweep().
    const records = new Float64Array(statics.count * GRID_RECORD)
    for (let shape = 0; shape < statics.count; shape++) {
      const r = shape * GRID_RECORD
      if (statics.kind[shape] === SHAPE_CIRCLE) {
        const p = shape * PARAMS_PER_SHAPE
        records[r] = statics.params[p]; records[r + 1] = statics.params[p + 1]; records[r + 2] = statics.params[p + 2]
      } else {
        records[r + 2] = -1
      }
    }
    this._gridRecords = records
  }

  // ---- bodies ----------------------------------------------------------

  /**
   * Adds a dynamic circle. Returns its id.
   * @param {object} def
   * @param {number} def.x @param {number} def.y @param {number} def.radius
   * @param {number} [def.vx] @param {number} [def.vy]
   * @param {number} [def.angle] @param {number} [def.angularVelocity]
   * @param {{density: number, restitution: number, friction: number}} [def.material]
   * @param {boolean} [def.collidesWithBodies] default true
   */
  createCircle (def) {
    const radius = def.radius
    if (!(radius > 0 && radius <= this.maxBodyRadius)) {
      throw new RangeError(`radius must be in (0, ${this.maxBodyRadius}]`)
    }
    const vx = def.vx ?? 0; const vy = def.vy ?? 0
    const angle = def.angle ?? 0; const angularVelocity = def.angularVelocity ?? 0
    if (!Number.isFinite(def.x + def.y + vx + vy + angle + angularVelocity)) {
      throw new RangeError('x, y, vx, vy, angle and angularVelocity must be finite numbers')
    }
    const material = def.material ?? METAL
    const id = this._freeCount > 0 ? this._freeIds[--this._freeCount] : this.bodyCount++
    if (id >= this.capacity) this._allocate(this.capacity * 2)
    // Solid disc: m = ρ·π·r², I = m·r²/2.
    const mass = material.density * Math.PI * radius * radius
    const st = this.state
    const b = id * STRIDE
    st[b + X] = st[b + PREVIOUS_X] = def.x
    st[b + Y] = st[b + PREVIOUS_Y] = def.y
    st[b + VX] = vx
    st[b + VY] = vy
    st[b + ANGLE] = st[b + PREVIOUS_ANGLE] = angle
    st[b + SPIN] = angularVelocity
    st[b + RADIUS] = radius
    st[b + INVERSE_MASS] = 1 / mass
    st[b + INVERSE_INERTIA] = 2 / (mass * radius * radius)
    st[b + RESTITUTION] = material.restitution
    st[b + FRICTION] = material.friction
    st[b + ALIVE] = 1
    // Ball–ball contacts: off for every drop (a drop's path depends on its seed alone), kept for the
    // general engine and its collision tests (restitution and friction between two bodies).
    const pairs = def.collidesWithBodies ?? true
    this.collidesWithBodies[id] = pairs ? 1 : 0
    if (pairs) this._pairCount++
    return id
  }

  /** @param {number} id */
  destroyBody (id) {
    if (!this.isAlive(id)) throw new RangeError(`no body ${id}`)
    this.state[id * STRIDE + ALIVE] = 0
    if (this.collidesWithBodies[id] === 1) this._pairCount--
    this.collidesWithBodies[id] = 0
    // Free ids are kept in descending order, so the lowest comes back first:
    // inserted in place in a typed array, so destroying allocates nothing.
    const free = this._freeIds
    let k = this._freeCount++
    while (k > 0 && free[k - 1] < id) { free[k] = free[k - 1]; k-- }
    free[k] = id
  }

  /** @param {number} id */
  isAlive (id) {
    return Number.isInteger(id) && id >= 0 && id < this.bodyCount && this.state[id * STRIDE + ALIVE] === 1
  }

  liveBodyCount () {
    let n = 0
    for (let i = 0; i < this.bodyCount; i++) n += this.state[i * STRIDE + ALIVE]
    return n
  }

  // ---- time ------------------------------------------------------------

  /**
   * Kept though the game steps its rooms tick by tick (the server's clock, the
   * page's RoomClock): the engine's own fixed step with accumulator and
   * interpolation alpha, for anyone embedding it in a render loop
   * (docs/engine.md); tests/engine/fixed-timestep.test.js holds it to that.
   * Advances by real elapsed time through the fixed-timestep accumulator.
   * Runs at most maxStepsPerUpdate steps (time beyond that is dropped, so a
   * long pause cannot spiral) and returns the interpolation alpha in [0, 1)
   * between the previous and the current state.
   * @param {number} frameTime seconds
   */
  update (frameTime) {
    const steps = this.clock.advance(frameTime)
    for (let s = 0; s < steps; s++) this.step()
    return this.clock.alpha
  }

  /** One fixed step of `timestep` seconds. Allocates nothing. */
  step () {
    if (this._staticsDirty) this._rebuildStaticGrid()
    const count = this.bodyCount
    this._advanceBodies(count)
    if (this._pairCount > 1) {
      this._pairHash.rebuild(this.state, STRIDE, this.collidesWithBodies, count)
      this._pairHash.forEachCandidatePair(count, this._solvePair)
    }
    this.tick++
  }

  /**
   * Moves every live body through its sub-steps against the static shapes,
   * in two loops on one set of locals. Most bodies, most steps, need one
   * sub-step and hit nothing: the first loop moves those itself and hands
   * the rest (a possible impact, a fast body) to the second, the full swept
   * path. A handed-over body keeps its state (only its previous pose is
   * recorded), and the arithmetic is the same, so both ways give the same
   * bits. Pegs are swept inline (no call per candidate): the same time of
   * impact as StaticShapes.sweep(), the reference, which segments go
   * through; tests/engine/sweep-reference.test.js holds the two to the bit.
   * @param {number} count
   */
  _advanceBodies (count) {
    const maxTravelPerSubstep = MAX_TRAVEL_PER_SUBSTEP // a local: a module constant costs a check on every read
    const gridRecord = GRID_RECORD
    const paramsPerShape = PARAMS_PER_SHAPE
    const slabTolerance = SLAB_TOLERANCE
    const dt = this.timestep
    const gx = this.gravityX
    const gy = this.gravityY
    const absGx = gx < 0 ? -gx : gx
    const absGy = gy < 0 ? -gy : gy
    const grid = this.staticGrid
    const cellStart = grid.cellStart
    const items = grid.items
    const records = this._gridRecords
    const shapeParams = this.statics.params
    const maxSubsteps = MAX_SUBSTEPS
    const maxImpacts = MAX_IMPACTS_PER_SUBSTEP
    const sweepDx = SWEEP_DX; const sweepDy = SWEEP_DY; const sweepTime = SWEEP_TIME
    const sweepNx = SWEEP_NX; const sweepNy = SWEEP_NY; const sweepDepth = SWEEP_DEPTH
    const statics = this.statics
    const sweep = this._sweep
    const contact = this._contact
    const st = this.state
    const handedOver = this._handedOver
    let handedOverCount = 0
    for (let i = 0, b = 0; i < count; i++, b += STRIDE) {
      if (st[b + ALIVE] !== 1) continue
      const x = st[b + X]; const y = st[b + Y]
      const angle0 = st[b + ANGLE]
      st[b + PREVIOUS_X] = x
      st[b + PREVIOUS_Y] = y
      st[b + PREVIOUS_ANGLE] = angle0
      let vx = st[b + VX]; let vy = st[b + VY]
      const radius = st[b + RADIUS]
      // The sub-step count as the full path works it out: more than one hands the body over.
      const speedX = (vx < 0 ? -vx : vx) + absGx * dt
      const speedY = (vy < 0 ? -vy : vy) + absGy * dt
      const travel2 = (speedX * speedX + speedY * speedY) * dt * dt
      const maxTravel = radius * maxTravelPerSubstep
      if (travel2 > maxTravel * maxTravel) { handedOver[handedOverCount++] = i; continue }
      vx += gx * dt
      vy += gy * dt
      const dx = vx * dt
      const dy = vy * dt
      const cell = grid.cellAt(x, y)
      if (cell >= 0) {
        const pathLength2 = dx * dx + dy * dy
        let clear = true
        for (let k = cellStart[cell], end = cellStart[cell + 1]; k < end; k++) {
          const r = items[k] * gridRecord
          const pegRadius = records[r + 2]
          if (pegRadius > 0) {
            const mx = x - records[r]; const my = y - records[r + 1]
            const along = mx * dx + my * dy
            const reach = radius + pegRadius
            const c = mx * mx + my * my - reach * reach
            if (pegPathMisses(along, c, pathLength2)) continue
          } else {
            const p = items[k] * paramsPerShape
            const nx = shapeParams[p + 4]; const ny = shapeParams[p + 5]
            const sideStart = (x - shapeParams[p]) * nx + (y - shapeParams[p + 1]) * ny
            if (segmentPathMisses(sideStart, sideStart + dx * nx + dy * ny, radius + slabTolerance)) continue
          }
          clear = false
          break
        }
        if (!clear) { handedOver[handedOverCount++] = i; continue }
      }
      let angle = angle0 + st[b + SPIN] * dt
      if (angle >= TWO_PI || angle < 0) angle -= Math.floor(angle / TWO_PI) * TWO_PI
      st[b + X] = x + dx; st[b + Y] = y + dy
      st[b + VX] = vx; st[b + VY] = vy
      st[b + ANGLE] = angle
    }
    // The rest: the full swept path of each handed-over body, sub-steps of at most
    // maxTravel, each a straight path swept against the static shapes, stopping
    // at every first impact to resolve it and carrying on with the new velocity.
    for (let k = 0; k < handedOverCount; k++) {
      const i = handedOver[k]
      const base = i * STRIDE
      let vx = st[base + VX]; let vy = st[base + VY]
      let angle = st[base + ANGLE]
      const radius = st[base + RADIUS]
      // Speed bound over the whole step (current speed plus what gravity adds),
      // compared squared so no root is needed.
      const speedX = (vx < 0 ? -vx : vx) + absGx * dt
      const speedY = (vy < 0 ? -vy : vy) + absGy * dt
      const travel2 = (speedX * speedX + speedY * speedY) * dt * dt
      const maxTravel = radius * maxTravelPerSubstep
      const maxTravel2 = maxTravel * maxTravel
      let substeps = 1
      while (substeps < maxSubsteps && travel2 > substeps * substeps * maxTravel2) substeps++
      const h = dt / substeps
      for (let s = 0; s < substeps; s++) {
        vx += gx * h
        vy += gy * h
        angle += st[base + SPIN] * h
        if (angle >= TWO_PI || angle < 0) angle -= Math.floor(angle / TWO_PI) * TWO_PI
        // Move along the straight sub-step path, stopping at each first impact
        // to resolve it, then carrying on with the new velocity.
        let remaining = 1
        for (let impact = 0; impact < maxImpacts && remaining > 0; impact++) {
          const x = st[base + X]; const y = st[base + Y]
          const cell = grid.cellAt(x, y)
          const dx = vx * h * remaining
          const dy = vy * h * remaining
          let first = -1
          let firstTime = 2
          if (cell >= 0) {
            const pathLength2 = dx * dx + dy * dy
            for (let k = cellStart[cell], end = cellStart[cell + 1]; k < end; k++) {
              const r = items[k] * gridRecord
              const pegRadius = records[r + 2]
              if (pegRadius > 0) {
                // Most candidates are pegs the path does not reach: reject
                // them first. The rest is the sweep of static-shapes.js
                // (sweepPoint), written out so a peg costs no call.
                const mx = x - records[r]; const my = y - records[r + 1]
                const b = mx * dx + my * dy
                const reach = radius + pegRadius
                const reach2 = reach * reach
                const c = mx * mx + my * my - reach2
                if (pegPathMisses(b, c, pathLength2)) continue
                if (c > 0) {
                  const discriminant = b * b - pathLength2 * c
                  if (discriminant < 0) continue
                  // The smaller root (-b - √D)/a as c/(-b + √D): no cancellation.
                  const t = c / (-b + Math.sqrt(discriminant))
                  if (t > 1 || !(t < firstTime)) continue
                  first = items[k]
                  firstTime = t
                  contact[sweepNx] = (mx + dx * t) / reach; contact[sweepNy] = (my + dy * t) / reach; contact[sweepDepth] = 0
                } else if (firstTime > 0) {
                  // Already touching and approaching: contact now.
                  const dist2 = c + reach2
                  first = items[k]
                  firstTime = 0
                  if (dist2 > 0) {
                    const dist = Math.sqrt(dist2)
                    contact[sweepNx] = mx / dist; contact[sweepNy] = my / dist; contact[sweepDepth] = reach - dist
                  } else {
                    contact[sweepNx] = 0; contact[sweepNy] = -1; contact[sweepDepth] = reach
                  }
                }
                continue
              }
              // A segment (wall).
              const shape = items[k]
              const p = shape * paramsPerShape
              const nx = shapeParams[p + 4]; const ny = shapeParams[p + 5]
              const sideStart = (x - shapeParams[p]) * nx + (y - shapeParams[p + 1]) * ny
              if (segmentPathMisses(sideStart, sideStart + dx * nx + dy * ny, radius + slabTolerance)) continue
              // Strictly earlier wins, so ties go to the lowest shape id.
              sweep[sweepDx] = dx; sweep[sweepDy] = dy
              if (statics.sweep(shape, st, base, sweep) && sweep[sweepTime] < firstTime) {
                first = shape
                firstTime = sweep[sweepTime]
                contact[sweepNx] = sweep[sweepNx]; contact[sweepNy] = sweep[sweepNy]; contact[sweepDepth] = sweep[sweepDepth]
              }
            }
          }
          if (first < 0) {
            st[base + X] = x + dx; st[base + Y] = y + dy
            break
          }
          st[base + X] = x + dx * firstTime; st[base + Y] = y + dy * firstTime
          remaining -= remaining * firstTime
          st[base + VX] = vx; st[base + VY] = vy
          solveStaticContact(st, base, statics, first, contact)
          vx = st[base + VX]; vy = st[base + VY]
        }
      }
      st[base + VX] = vx; st[base + VY] = vy
      st[base + ANGLE] = angle
    }
  }

  _collidePair (i, j) {
    const st = this.state
    const bi = i * STRIDE; const bj = j * STRIDE
    const dx = st[bi + X] - st[bj + X]
    const dy = st[bi + Y] - st[bj + Y]
    const reach = st[bi + RADIUS] + st[bj + RADIUS]
    const dist2 = dx * dx + dy * dy
    if (dist2 >= reach * reach) return
    const contact = this._pairContact
    if (dist2 > 0) {
      const dist = Math.sqrt(dist2)
      contact[0] = dx / dist; contact[1] = dy / dist; contact[2] = reach - dist
    } else {
      contact[0] = 0; contact[1] = -1; contact[2] = reach
    }
    solveBodyContact(st, bi, bj, contact)
  }

  // ---- state -----------------------------------------------------------

  /**
   * Hash of the exact bits of every live body's state (id, position,
   * velocity, angle, angular velocity), in id order, plus the tick.
   * @returns {string} 16 hex digits
   */
  stateHash () {
    const h = this._hasher.reset()
    h.addInt32(this.tick)
    for (let i = 0; i < this.bodyCount; i++) {
      if (this.state[i * STRIDE + ALIVE] !== 1) continue
      h.addInt32(i)
      this._hashBody(h, i)
    }
    return h.digestHex()
  }

  /** Hash of one body's state bits alone (independent of id and tick). */
  bodyStateHash (id) {
    if (!this.isAlive(id)) throw new RangeError(`no body ${id}`)
    const h = this._hasher.reset()
    this._hashBody(h, id)
    return h.digestHex()
  }

  _hashBody (h, i) {
    const st = this.state
    const b = i * STRIDE
    h.addFloat64(st[b + X]).addFloat64(st[b + Y])
      .addFloat64(st[b + VX]).addFloat64(st[b + VY])
      .addFloat64(st[b + ANGLE]).addFloat64(st[b + SPIN])
  }

  /**
   * Interpolated pose for rendering, into out[0..2] = x, y, angle. (The
   * seeds-mode page applies the same formula to the states it records:
   * client/seeded-room.js.)
   * @param {number} id @param {number} alpha from update()
   * @param {Float64Array | number[]} out
   */
  interpolatedPose (id, alpha, out) {
    const st = this.state
    const b = id * STRIDE
    out[0] = st[b + PREVIOUS_X] + (st[b + X] - st[b + PREVIOUS_X]) * alpha
    out[1] = st[b + PREVIOUS_Y] + (st[b + Y] - st[b + PREVIOUS_Y]) * alpha
    let da = st[b + ANGLE] - st[b + PREVIOUS_ANGLE]
    if (da > Math.PI) da -= TWO_PI
    else if (da < -Math.PI) da += TWO_PI
    out[2] = st[b + PREVIOUS_ANGLE] + da * alpha
    return out
  }

  /** Kinetic + gravitational potential energy of all live bodies: what the collision tests hold to "never grows". */
  totalEnergy () {
    let energy = 0
    for (let i = 0; i < this.bodyCount; i++) {
      if (this.state[i * STRIDE + ALIVE] !== 1) continue
      const b = i * STRIDE
      const st = this.state
      const m = 1 / st[b + INVERSE_MASS]
      const inertia = 1 / st[b + INVERSE_INERTIA]
      const v2 = st[b + VX] * st[b + VX] + st[b + VY] * st[b + VY]
      const w = st[b + SPIN]
      energy += 0.5 * m * v2 + 0.5 * inertia * w * w - m * (this.gravityX * st[b + X] + this.gravityY * st[b + Y])
    }
    return energy
  }
}
