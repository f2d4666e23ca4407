/**
 * What the player sees of a seeds-mode room: every ball drawn from the
 * page's own fixed-step simulation of its drop, at (room tick − start
 * tick), with no position from the server at all.
 *
 * Each ball gets a DropSimulator of its own (balls do not collide, so a
 * drop's path depends on its seed and the board only), stepped one fixed
 * engine step at a time as the room clock passes each tick; each step's
 * state is recorded. A render tick t between steps i and i + 1 draws the
 * engine's interpolation between them (World.interpolatedPose's formula,
 * on the recorded states, with the accumulator's alpha = t − ⌊t⌋), so at
 * every whole tick the drawn position is the engine's, bit for bit. A drop that arrives late
 * (another player's, batched every 1/EVENT_HZ; one joined mid-flight) is
 * stepped to where it is before it is drawn: fast-forwarded, never drawn
 * in the wrong place.
 *
 * The simulation may run ahead of the drawing (the desync check needs the
 * states at the server's tick, a settlement needs the landing), never
 * behind it. The recorded states also give the trail, the peg contacts
 * (glows, ticks) and the desync check's flight hash (the server's
 * FlightHasher over x, y, vx, vy, by slot). Nothing here decides money:
 * balances and own results come from the server, and the landing is what
 * the page's verifier checks against the server's settlement.
 */
import { DropSimulator } from '/engine/index.js'
import { FlightHasher } from '/protocol/drop-events-codec.js'
import { payoutMilli, toCredits } from '/protocol/payout.js'
import { PegContactTracker } from './peg-contacts.js'
import { LANDED_LINGER_TICKS, BUCKET_REST_DEPTH } from './room-view.js'

/** Contacts and landings this many ticks older than the render tick are not reported (a drop fast-forwarded). */
const STALE_EVENT_TICKS = 4
/** States recorded per tick: x, y, angle (the trajectory's layout), and vx, vy (for the flight hash). */
const POSE = 3
const VELOCITY = 2
const FIRST_CAPACITY = 256
const MAX_SEEN = 10_000
const TWO_PI = 2 * Math.PI

/**
 * One ball's simulation: its own DropSimulator (from a pool), the steps
 * taken and every state reached.
 * @typedef {object} Flight
 * @property {import('./drop-verifier.js').LocalDrop} drop
 * @property {import('/engine/board.js').Board} board
 * @property {DropSimulator | null} simulator null once landed (back in the pool)
 * @property {number} body @property {number} stepped steps taken so far
 * @property {Float64Array} path x, y, angle after each step (index 0: the release)
 * @property {Float64Array} velocity vx, vy after each step
 * @property {number} landedAt steps to landing, -1 while in flight
 * @property {{ tick: number, peg: number, row: number }[]} contacts @property {number} contactCursor
 * @property {PegContactTracker} tracker
 * @property {number} firstDrawnAge ticks since release when first drawn (-1: not yet); above 0 = fast-forwarded
 */

export class SeededRoom {
  /**
   * @param {object} options
   * @param {string} options.room
   * @param {import('/engine/board.js').Board} options.board the room's board (newest engine version the room runs)
   * @param {(engineVersion: string) => import('/engine/board.js').Board} [options.boardFor] the room's board under a drop's engine version
   * @param {(drop: import('./drop-verifier.js').LocalDrop) => void} [options.onLanded] a ball landed in the simulation (its outcome is on the drop now)
   */
  constructor ({ room, board, boardFor = () => board, onLanded = () => {} }) {
    this.room = room
    this.board = board
    this.boardFor = boardFor
    this.onLanded = onLanded
    /** @type {Map<number, import('./drop-verifier.js').LocalDrop>} */
    this.drops = new Map()
    /** @type {Map<number, Flight>} */
    this._flights = new Map()
    /** @type {Map<object, DropSimulator[]>} idle simulators by board */
    this._pool = new Map()
    /**
     * Landings not yet shown (the caller empties it); `stale`: long before this frame.
     * @type {{ bucket: number, mine: boolean, dropId: number, drop: import('./drop-verifier.js').LocalDrop, stale: boolean }[]}
     */
    this.landings = []
    /** @type {import('./room-view.js').PegHit[]} */
    this.pegHits = []
    /** Drop ids whose ball left the board (landed and faded), for a caller that mirrors `drops` elsewhere and empties it (null: not kept). @type {number[] | null} */
    this.retired = null
    /** Seeds mode draws no ball it cannot explain. */
    this.unknownDrawn = 0
    this.lastTick = null
    /** `frames` and `frameMs`: posesAt() calls and the time they took (the page's own cost per frame, for scripts/page-frame-cost.js) */
    this.stats = { drops: 0, steps: 0, fastForwarded: 0, fastForwardSteps: 0, checks: 0, mismatches: 0, frames: 0, frameMs: 0 }
    /** @type {{ dropId: number, tick: number, x: number, y: number }[] | null} drawn positions, when tracing */
    this.trace = null
    this._poses = []
    this._posePool = []
    this._out = new Float64Array(3)
    this._hasher = new FlightHasher()
    /** Drop ids put on the board (a batch may name one again), the latest MAX_SEEN. */
    this._seen = new Set()
    /** Balls in the last flight hash. */
    this.hashedBalls = 0
  }

  /** The player's own balls not landed yet at the last rendered tick. */
  get ownInFlight () {
    let count = 0
    for (const flight of this._flights.values()) {
      const drop = flight.drop
      if (drop.mine && (this.lastTick === null || flight.landedAt < 0 || this.lastTick - drop.startTick <= flight.landedAt)) count++
    }
    return count
  }

  /** Whether this drop was put on the board (still there, or landed and gone). @param {number} dropId */
  has (dropId) {
    return this._seen.has(dropId)
  }

  /**
   * Puts an announced drop's ball on the board (once per drop id); it is
   * simulated from its seed as the clock reaches it.
   * @param {import('./drop-verifier.js').LocalDrop} drop
   */
  add (drop) {
    if (!firstSighting(this._seen, drop.dropId)) return
    const board = this.boardFor(drop.engineVersion)
    const simulator = this._simulator(board)
    const body = simulator.addDrop(drop.dropSeed, drop)
    const path = new Float64Array(POSE * FIRST_CAPACITY)
    const velocity = new Float64Array(VELOCITY * FIRST_CAPACITY)
    const world = simulator.world
    path[0] = world.xOf(body); path[1] = world.yOf(body); path[2] = world.angleOf(body)
    velocity[0] = world.vxOf(body); velocity[1] = world.vyOf(body)
    /** @type {Flight} */
    const flight = { drop, board, simulator, body, stepped: 0, path, velocity, landedAt: -1, contacts: [], contactCursor: 0, tracker: new PegContactTracker(board), firstDrawnAge: -1 }
    flight.tracker.at(0, path[0], path[1], flight.contacts)
    this.drops.set(drop.dropId, drop)
    this._flights.set(drop.dropId, flight)
    this.stats.drops++
  }

  /**
   * Steps a drop's ball to its landing now (its settlement came before
   * the drawing got there); the drawing still follows the clock.
   * @param {number} dropId
   */
  complete (dropId) {
    const flight = this._flights.get(dropId)
    if (flight) this._advance(flight, Infinity)
  }

  /**
   * Ball poses at render tick `tick` (fractional). The returned array and
   * its poses are reused by the next call.
   * @param {number} tick
   * @returns {import('./room-view.js').BallPose[]}
   */
  posesAt (tick) {
    const started = performance.now()
    const poses = this._poses
    poses.length = 0
    this.lastTick = tick
    for (const flight of this._flights.values()) {
      const drop = flight.drop
      const age = tick - drop.startTick
      if (age < 0) continue
      const whole = Math.floor(age)
      this._advance(flight, whole + 1)
      const landedAt = flight.landedAt
      if (landedAt >= 0 && age > landedAt + LANDED_LINGER_TICKS) {
        this._reportLanding(flight, age)
        this._retire(flight)
        continue
      }
      if (landedAt >= 0 && age > landedAt) {
        this._reportLanding(flight, age)
        poses.push(this._landedPose(flight, age - landedAt))
        continue
      }
      if (flight.firstDrawnAge < 0) {
        flight.firstDrawnAge = age
        if (whole > 0) {
          this.stats.fastForwarded++
          this.stats.fastForwardSteps += whole
        }
      }
      this._reportContacts(flight, age)
      const pose = this._pose()
      this._interpolate(flight, whole, age - whole, pose)
      pose.mine = drop.mine
      pose.alpha = 1
      pose.dropId = drop.dropId
      pose.trajectory = flight.path
      pose.age = age
      poses.push(pose)
      if (this.trace && this.trace.length < 50_000) this.trace.push({ dropId: drop.dropId, tick, x: pose.x, y: pose.y })
    }
    this.stats.frames++
    this.stats.frameMs += performance.now() - started
    return poses
  }

  /**
   * The desync check's hash of the balls in flight at room tick `tick`
   * (protocol/drop-events-codec.js FlightHasher): each ball is stepped to
   * that tick if it has not got there yet.
   * @param {number} tick
   * @returns {string} 16 hex digits
   */
  flightHash (tick) {
    const inFlight = []
    for (const flight of this._flights.values()) {
      const age = tick - flight.drop.startTick
      if (age < 0) continue
      this._advance(flight, age)
      if (flight.landedAt >= 0 && flight.landedAt <= age) continue
      inFlight.push(flight)
    }
    inFlight.sort((p, q) => p.drop.slot - q.drop.slot)
    this.hashedBalls = inFlight.length
    const hasher = this._hasher.begin(tick)
    for (const flight of inFlight) {
      const age = tick - flight.drop.startTick
      const p = POSE * age
      const v = VELOCITY * age
      hasher.add(flight.drop.slot, flight.path[p], flight.path[p + 1], flight.velocity[v], flight.velocity[v + 1])
    }
    return hasher.digest()
  }

  /**
   * Compares the server's flight hash at `tick` with this page's.
   * @param {number} tick @param {string} hash
   * @returns {{ ok: boolean, tick: number, server: string, local: string, balls: number }}
   */
  check (tick, hash) {
    const local = this.flightHash(tick)
    this.stats.checks++
    const ok = local === hash
    if (!ok) this.stats.mismatches++
    return { ok, tick, server: hash, local, balls: this.hashedBalls }
  }

  /** Engine state of a drop's ball after `steps` steps, for tests: { x, y, angle } or null if not simulated that far. */
  stateOf (dropId, steps) {
    const flight = this._flights.get(dropId)
    if (!flight || steps > flight.stepped) return null
    const p = POSE * steps
    return { x: flight.path[p], y: flight.path[p + 1], angle: flight.path[p + 2] }
  }

  /** Steps `flight` until it has taken `steps` steps or landed; a landing fills in the drop's outcome. */
  _advance (flight, steps) {
    const simulator = flight.simulator
    if (simulator === null || flight.stepped >= steps) return
    const world = simulator.world
    const body = flight.body
    let path = flight.path
    let velocity = flight.velocity
    while (flight.stepped < steps) {
      const landed = simulator.step()
      const n = ++flight.stepped
      this.stats.steps++
      if (POSE * (n + 1) > path.length) {
        path = grow(path)
        velocity = grow(velocity)
        flight.path = path
        flight.velocity = velocity
      }
      const p = POSE * n
      const v = VELOCITY * n
      if (landed.length > 0) {
        const { bucket, ticks, stateHash, x, y, angle } = landed[0]
        path[p] = x; path[p + 1] = y; path[p + 2] = angle
        // The body is gone; its velocity is not part of any flight hash (a landed ball is not in flight).
        velocity[v] = 0; velocity[v + 1] = 0
        flight.tracker.at(n, x, y, flight.contacts)
        this._landed(flight, { bucket, ticks, stateHash })
        return
      }
      path[p] = world.xOf(body); path[p + 1] = world.yOf(body); path[p + 2] = world.angleOf(body)
      velocity[v] = world.vxOf(body); velocity[v + 1] = world.vyOf(body)
      flight.tracker.at(n, path[p], path[p + 1], flight.contacts)
    }
  }

  _landed (flight, { bucket, ticks, stateHash }) {
    const drop = flight.drop
    flight.landedAt = ticks
    this._release(flight)
    drop.bucket = bucket
    drop.ticks = ticks
    drop.stateHash = stateHash
    drop.trajectory = flight.path.subarray(0, POSE * (ticks + 1))
    if (!drop.mine) {
      // Another player's result as this page's simulation has it (the
      // server sends no `settled` for it in seeds mode): for the feed only.
      const multiplier = flight.board.multipliers[bucket]
      drop.result = { dropId: drop.dropId, player: drop.player, bet: drop.bet ?? 0, multiplier, payout: toCredits(payoutMilli(drop.bet ?? 0, multiplier)) }
    }
    this.onLanded(drop)
  }

  /**
   * The engine's interpolation between the states after steps `i` and
   * i + 1 (World.interpolatedPose, on the recorded states): previous +
   * (current − previous) · alpha, the angle the short way round.
   */
  _interpolate (flight, i, alpha, pose) {
    const path = flight.path
    const last = flight.landedAt >= 0 ? flight.landedAt : flight.stepped
    const k = POSE * i
    const n = i < last ? k + POSE : k
    pose.x = path[k] + (path[n] - path[k]) * alpha
    pose.y = path[k + 1] + (path[n + 1] - path[k + 1]) * alpha
    let da = path[n + 2] - path[k + 2]
    if (da > Math.PI) da -= TWO_PI
    else if (da < -Math.PI) da += TWO_PI
    pose.angle = path[k + 2] + da * alpha
  }

  _reportContacts (flight, age) {
    const contacts = flight.contacts
    while (flight.contactCursor < contacts.length && contacts[flight.contactCursor].tick <= age) {
      const contact = contacts[flight.contactCursor++]
      if (contact.tick >= age - STALE_EVENT_TICKS) this.pegHits.push({ peg: contact.peg, row: contact.row, mine: flight.drop.mine })
    }
  }

  _reportLanding (flight, age) {
    const drop = flight.drop
    if (drop.landingShown) return
    drop.landingShown = true
    this._reportContacts(flight, flight.landedAt)
    this.landings.push({ bucket: drop.bucket, mine: drop.mine, dropId: drop.dropId, drop, stale: age - flight.landedAt > STALE_EVENT_TICKS })
  }

  _landedPose (flight, since) {
    const board = this.board
    const path = flight.path
    const end = POSE * flight.landedAt
    const landY = path[end + 1]
    const t = Math.min(1, since / 8)
    const pose = this._pose()
    pose.x = path[end]
    pose.y = landY + (board.bucketLineY + BUCKET_REST_DEPTH * board.bucketWidth - landY) * t
    pose.angle = path[end + 2]
    pose.mine = flight.drop.mine
    pose.alpha = 1 - since / LANDED_LINGER_TICKS
    pose.dropId = flight.drop.dropId
    pose.trajectory = null
    pose.age = since
    return pose
  }

  /** A pose object from this frame's pool (the renderer reads them before the next frame). */
  _pose () {
    const i = this._poses.length
    let pose = this._posePool[i]
    if (!pose) this._posePool[i] = pose = { x: 0, y: 0, angle: 0, mine: false, alpha: 1, dropId: -1, deviation: 0, trajectory: null, age: 0, ox: 0, oy: 0 }
    return pose
  }

  _retire (flight) {
    this._release(flight)
    this._flights.delete(flight.drop.dropId)
    this.drops.delete(flight.drop.dropId)
    this.retired?.push(flight.drop.dropId)
  }

  /** A simulator with no ball in flight, from the pool. */
  _simulator (board) {
    const idle = this._pool.get(board)
    return idle && idle.length > 0 ? idle.pop() : new DropSimulator(board)
  }

  _release (flight) {
    const simulator = flight.simulator
    if (simulator === null) return
    flight.simulator = null
    if (simulator.inFlight !== 0) return // retired in flight (never happens while drawing): not reusable
    let idle = this._pool.get(flight.board)
    if (!idle) this._pool.set(flight.board, (idle = []))
    idle.push(simulator)
  }
}

/**
 * Records a drop id as put on a board (the latest MAX_SEEN are kept: a
 * batch may name a drop again); false if it was already.
 * @param {Set<number>} seen @param {number} dropId
 */
export function firstSighting (seen, dropId) {
  if (seen.has(dropId)) return false
  seen.add(dropId)
  if (seen.size > MAX_SEEN) seen.delete(seen.values().next().value)
  return true
}

function grow (array) {
  const grown = new Float64Array(array.length * 2)
  grown.set(array)
  return grown
}
