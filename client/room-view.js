/**
 * What the player sees of one room: the balls in flight, positioned at a
 * (fractional) render tick from the server's snapshots.
 *
 * Between two snapshots a and b a ball is placed at the straight-line
 * interpolation of its two snapshot positions, plus the local simulation's
 * deviation from its own straight line between the same two ticks:
 *
 *   p(t) = lerp(snap_a, snap_b, α) + (sim(t) − lerp(sim(a), sim(b), α))
 *
 * so the ball follows its real curved path around pegs instead of cutting
 * corners, while staying anchored to the server's positions at every
 * snapshot tick. When the next snapshot is late (the render tick has passed
 * the newest one), the ball carries on from the last snapshot along the
 * simulated path, which is where the server has it too: nothing freezes
 * or jumps. A snapshot slot is matched to its drop by tick: a slot is
 * reused once its ball has landed, and the local simulation says when.
 *
 * The view also reports what the simulation says happened since the last
 * frame — peg contacts (for glows and ticks) and landings — so every
 * effect the page draws is one the simulation had.
 */
import { pegContacts } from './peg-contacts.js'

/** A landed ball stays visible in its bucket this many ticks, fading out. */
export const LANDED_LINGER_TICKS = 36
/** A landed ball sinks this far below the bucket line (into the bucket box) while it fades, in bucket widths. */
export const BUCKET_REST_DEPTH = 8 / 36
/** Positions in snapshots are rounded to 0.5 px: at most 0.25 px off. */
const SNAPSHOT_TOLERANCE_PX = 0.25 + 1e-6
/**
 * A ball in a snapshot that no announced drop explains is drawn only while
 * that snapshot is this recent (in snapshot intervals): with the server
 * down, the last snapshot's entries must not stay on the board as frozen
 * "ghosts" once the real balls have landed.
 */
const UNKNOWN_BALL_HOLD = 1.5
/** Contacts and landings this many ticks older than the render tick are not reported (a drop joined mid-flight). */
const STALE_EVENT_TICKS = 4

/**
 * @typedef {object} BallPose
 * @property {number} x @property {number} y @property {number} angle
 * @property {boolean} mine @property {number} alpha opacity 0..1
 * @property {number} dropId (-1: a ball the page has no announcement for)
 * @property {number} deviation px between this position and the local simulation's at the same tick
 * @property {Float64Array | null} [trajectory] the simulated path (for the trail), with
 * @property {number} [age] ticks since release, and @property {number} [ox] @property {number} [oy] the offset drawn from it
 */

/**
 * @typedef {object} PegHit a peg contact of the simulation, reached by the render clock
 * @property {number} peg @property {number} row @property {boolean} mine
 */

export class RoomView {
  /**
   * @param {object} options
   * @param {string} options.room
   * @param {import('/engine/board.js').Board} options.board
   * @param {{ positions: number, mismatches: number, unknown: number }} [options.snapshotChecks] counters to add to (shared across rooms)
   */
  constructor ({ room, board, snapshotChecks = { positions: 0, mismatches: 0, unknown: 0 }, snapshotEvery = 3 }) {
    this.room = room
    this.board = board
    /** @type {Map<number, import('./drop-verifier.js').LocalDrop>} */
    this.drops = new Map()
    /** @type {Map<number, import('./drop-verifier.js').LocalDrop[]>} drops by slot, by start tick */
    this._bySlot = new Map()
    /** Every snapshot position compared with the local simulation. */
    this.snapshotChecks = snapshotChecks
    /**
     * Landings not yet shown (the caller empties it); `stale`: it happened
     * well before this frame (a hidden tab, a drop joined late): record it, skip its effects.
     * @type {{ bucket: number, mine: boolean, dropId: number, drop: import('./drop-verifier.js').LocalDrop, stale: boolean }[]}
     */
    this.landings = []
    /** @type {PegHit[]} peg contacts reached since the last frame (the caller empties it) */
    this.pegHits = []
    this.snapshotEvery = snapshotEvery
    /** Balls drawn in the last frame that no announcement explains. */
    this.unknownDrawn = 0
    /** The last render tick posesAt was asked for. */
    this.lastTick = null
    this._poses = []
  }

  /** The player's own balls not landed yet at the last rendered tick. */
  get ownInFlight () {
    let count = 0
    for (const drop of this.drops.values()) {
      if (drop.mine && (this.lastTick === null || this.lastTick - drop.startTick <= drop.ticks)) count++
    }
    return count
  }

  /** @param {import('./drop-verifier.js').LocalDrop} drop */
  add (drop) {
    if (this.drops.has(drop.dropId)) return
    if (drop.trajectory && !drop.contacts) {
      drop.contacts = pegContacts(this.board, drop.trajectory)
      drop.contactCursor = 0
    }
    this.drops.set(drop.dropId, drop)
    let list = this._bySlot.get(drop.slot)
    if (!list) this._bySlot.set(drop.slot, (list = []))
    list.push(drop)
    list.sort((p, q) => p.startTick - q.startTick)
  }

  /** The drop whose ball occupied `slot` at snapshot tick `tick`, or null. */
  dropInSlot (slot, tick) {
    const list = this._bySlot.get(slot)
    if (!list) return null
    for (let i = list.length - 1; i >= 0; i--) {
      const drop = list[i]
      if (drop.startTick < tick && tick < drop.startTick + drop.ticks) return drop
    }
    return null
  }

  /**
   * Checks a snapshot's positions against the local simulations.
   * @param {import('/protocol/snapshot-codec.js').Snapshot} snapshot
   */
  check (snapshot) {
    for (let i = 0; i < snapshot.slots.length; i++) {
      const drop = this.dropInSlot(snapshot.slots[i], snapshot.tick)
      if (!drop) { this.snapshotChecks.unknown++; continue }
      const k = 3 * (snapshot.tick - drop.startTick)
      this.snapshotChecks.positions++
      if (Math.abs(drop.trajectory[k] - snapshot.xs[i]) > SNAPSHOT_TOLERANCE_PX ||
          Math.abs(drop.trajectory[k + 1] - snapshot.ys[i]) > SNAPSHOT_TOLERANCE_PX) this.snapshotChecks.mismatches++
    }
  }

  /**
   * Ball poses at render tick `tick`, between snapshots `a` and `b`.
   * The returned array is reused by the next call.
   * @param {number} tick
   * @param {import('/protocol/snapshot-codec.js').Snapshot | null} a
   * @param {import('/protocol/snapshot-codec.js').Snapshot | null} b
   * @returns {BallPose[]}
   */
  posesAt (tick, a, b) {
    const poses = this._poses
    poses.length = 0
    this.lastTick = tick
    this.unknownDrawn = 0
    const alpha = a && b ? (tick - a.tick) / (b.tick - a.tick) : 0
    for (const drop of this.drops.values()) {
      const age = tick - drop.startTick
      if (age < 0) continue
      if (age > drop.ticks + LANDED_LINGER_TICKS) {
        if (!drop.landingShown) {
          drop.landingShown = true
          this.landings.push({ bucket: drop.bucket, mine: drop.mine, dropId: drop.dropId, drop, stale: true })
        }
        this._retire(drop)
        continue
      }
      if (age > drop.ticks) {
        poses.push(this._landedPose(drop, age - drop.ticks))
        continue
      }
      this._reportContacts(drop, age)
      const sim = simulatedPose(drop, age, simNow)
      const sa = a ? this._entry(a, drop) : -1
      const sb = b ? this._entry(b, drop) : -1
      let x = sim.x
      let y = sim.y
      if (sa >= 0 && sb >= 0) {
        const pa = simulatedPose(drop, a.tick - drop.startTick, simA)
        const pb = simulatedPose(drop, b.tick - drop.startTick, simB)
        x = lerp(a.xs[sa], b.xs[sb], alpha) + (sim.x - lerp(pa.x, pb.x, alpha))
        y = lerp(a.ys[sa], b.ys[sb], alpha) + (sim.y - lerp(pa.y, pb.y, alpha))
      } else if (sa >= 0 || sb >= 0) {
        const s = sa >= 0 ? a : b
        const i = sa >= 0 ? sa : sb
        const anchor = simulatedPose(drop, s.tick - drop.startTick, simA)
        x = s.xs[i] + (sim.x - anchor.x)
        y = s.ys[i] + (sim.y - anchor.y)
      }
      const deviation = Math.sqrt((x - sim.x) * (x - sim.x) + (y - sim.y) * (y - sim.y))
      poses.push({ x, y, angle: sim.angle, mine: drop.mine, alpha: 1, dropId: drop.dropId, deviation, trajectory: drop.trajectory, age, ox: x - sim.x, oy: y - sim.y })
    }
    // Balls in snapshots that no announcement explains (should not happen):
    // plain interpolation, and only from a recent snapshot (never frozen ghosts).
    if (a && (b || tick - a.tick <= UNKNOWN_BALL_HOLD * this.snapshotEvery)) {
      for (let i = 0; i < a.slots.length; i++) {
        if (this.dropInSlot(a.slots[i], a.tick)) continue
        const j = b ? indexOfSlot(b, a.slots[i]) : -1
        const x = j >= 0 ? lerp(a.xs[i], b.xs[j], alpha) : a.xs[i]
        const y = j >= 0 ? lerp(a.ys[i], b.ys[j], alpha) : a.ys[i]
        poses.push({ x, y, angle: 0, mine: false, alpha: 1, dropId: -1, deviation: 0 })
        this.unknownDrawn++
      }
    }
    return poses
  }

  /** Index of `drop` in snapshot `s` if the entry there is this drop's ball, else -1. */
  _entry (s, drop) {
    if (!(drop.startTick < s.tick && s.tick < drop.startTick + drop.ticks)) return -1
    return indexOfSlot(s, drop.slot)
  }

  /** Reports the contacts of `drop` the render clock has reached (once each). */
  _reportContacts (drop, age) {
    const contacts = drop.contacts
    if (!contacts) return
    while (drop.contactCursor < contacts.length && contacts[drop.contactCursor].tick <= age) {
      const contact = contacts[drop.contactCursor++]
      if (contact.tick >= age - STALE_EVENT_TICKS) this.pegHits.push({ peg: contact.peg, row: contact.row, mine: drop.mine })
    }
  }

  _landedPose (drop, since) {
    const end = 3 * drop.ticks
    const landY = drop.trajectory[end + 1]
    const t = Math.min(1, since / 8)
    if (!drop.landingShown) {
      drop.landingShown = true
      this._reportContacts(drop, drop.ticks)
      this.landings.push({ bucket: drop.bucket, mine: drop.mine, dropId: drop.dropId, drop, stale: since > STALE_EVENT_TICKS })
    }
    return {
      x: drop.trajectory[end],
      y: landY + (this.board.bucketLineY + BUCKET_REST_DEPTH * this.board.bucketWidth - landY) * t,
      angle: drop.trajectory[end + 2],
      mine: drop.mine,
      alpha: 1 - since / LANDED_LINGER_TICKS,
      dropId: drop.dropId,
      deviation: 0
    }
  }

  _retire (drop) {
    this.drops.delete(drop.dropId)
    const list = this._bySlot.get(drop.slot)
    const i = list ? list.indexOf(drop) : -1
    if (i >= 0) list.splice(i, 1)
  }
}

const simNow = { x: 0, y: 0, angle: 0 }
const simA = { x: 0, y: 0, angle: 0 }
const simB = { x: 0, y: 0, angle: 0 }

/**
 * The simulated pose at a fractional age (ticks since release), written to `out`.
 * @param {import('./drop-verifier.js').LocalDrop} drop @param {number} age @param {{ x: number, y: number, angle: number }} out
 */
function simulatedPose (drop, age, out) {
  const trajectory = drop.trajectory
  const last = drop.ticks
  const clamped = age < 0 ? 0 : (age > last ? last : age)
  const i = Math.floor(clamped)
  const f = clamped - i
  const k = 3 * i
  const n = i < last ? k + 3 : k
  out.x = trajectory[k] + (trajectory[n] - trajectory[k]) * f
  out.y = trajectory[k + 1] + (trajectory[n + 1] - trajectory[k + 1]) * f
  out.angle = trajectory[k + 2] + (trajectory[n + 2] - trajectory[k + 2]) * f
  return out
}

function indexOfSlot (snapshot, slot) {
  const slots = snapshot.slots
  let lo = 0
  let hi = slots.length - 1
  while (lo <= hi) {
    const mid = (lo + hi) >> 1
    if (slots[mid] === slot) return mid
    if (slots[mid] < slot) lo = mid + 1
    else hi = mid - 1
  }
  return -1
}

function lerp (p, q, t) {
  return p + (q - p) * t
}
