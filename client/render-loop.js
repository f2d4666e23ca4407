import { ENGINE_VERSION } from '/engine/index.js'
import { byId } from './dom.js'
import { pegRowCount } from './peg-contacts.js'

/**
 * The page's frames: each one reads the joined room's balls at the render
 * clock's tick and draws them, plays the peg glows and ticks and the
 * landings the view met on the way, and skips drawing when nothing moves.
 * Once a second, the footer's figures (rtt, buffer, snapshot checks).
 */
export class RenderLoop {
  /** @param {import('./player.js').PlayerPage} page */
  constructor (page) {
    this.page = page
    /** balls drawn in the last frame: all, those no announcement explains, and the player's own */
    this.lastFrame = { balls: 0, unknown: 0, mine: 0 }
    /** performance.now() of the first frame with the board drawn */
    this.firstBoardFrameAt = null
    /** @type {{ now: number, tick: number, balls: number, deviation: number, a: number | null, b: number | null }[] | null} per-frame record, when tracing */
    this.trace = null
    /** the last frame drawn had nothing moving (so the next such frame is skipped) */
    this.idleDrawn = false
  }

  start () {
    /** The room whose frames the board worker draws on its own: no animation frame here meanwhile. @type {import('./worker-seeded-room.js').WorkerSeededRoom | null} */
    this.parked = null
    this._requested = false
    this._frame = (now) => {
      this._requested = false
      this.frame(now)
      if (this.parked === null) this._request()
    }
    this._request()
    setInterval(() => this.updateFooter(), 1000)
  }

  _request () {
    if (this._requested) return
    this._requested = true
    requestAnimationFrame(this._frame)
  }

  frame (now) {
    const { connection: { view, timeline }, renderer } = this.page
    // The first frame drawn (in a worker, answered after this frame's task), whether or not anything moves now.
    if (this.firstBoardFrameAt === null && renderer.frames > 0) this.firstBoardFrameAt = performance.now()
    let poses = []
    if (view?.drawsInWorker) return this.park(view)
    if (view && timeline) {
      const tick = timeline.advance(now)
      if (tick !== null) {
        const { a, b } = timeline.bracket(tick)
        poses = view.posesAt(tick, a, b)
        if (this.trace && poses.length > 0 && this.trace.length < 20_000) this.record(now, tick, poses, a, b)
      }
      let mine = 0
      for (const pose of poses) if (pose.mine) mine++
      this.lastFrame = { balls: poses.length, unknown: view.unknownDrawn, mine }
      this.playEvents(view, now)
    }
    // Nothing moves: keep the last frame.
    if (this.keepsLastFrame(poses.length > 0)) return
    renderer.draw(poses, now)
    if (this.firstBoardFrameAt === null && renderer.frames > 0) this.firstBoardFrameAt = performance.now()
  }

  /**
   * A room simulated and drawn in the board worker (worker-seeded-room.js)
   * on the worker's own animation frames: this loop asks for none until
   * the room is closed (an animation frame costs the main thread its
   * rendering lifecycle even when nothing on the page changes), and plays
   * what each of the worker's reports met: the sounds, the landings.
   * @param {import('./worker-seeded-room.js').WorkerSeededRoom} view
   */
  park (view) {
    this.parked = view
    view.onReport = (report) => this.workerReported(view, report)
    view.onClose = () => {
      if (this.parked !== view) return
      this.parked = null
      this.idleDrawn = false
      this._request()
    }
  }

  /** @param {import('./worker-seeded-room.js').WorkerSeededRoom} view @param {import('./board-worker-room.js').DrivenReport} report */
  workerReported (view, report) {
    const { renderer } = this.page
    const now = performance.now()
    renderer.countDrawnEffects(report.drawn)
    if (this.firstBoardFrameAt === null && renderer.frames > 0) this.firstBoardFrameAt = now
    this.lastFrame = { balls: view.balls, unknown: 0, mine: view.mineDrawn }
    this.playEvents(view, now, { drawn: true })
  }

  /**
   * Whether this frame can keep the last one: nothing moves, no effect runs
   * and the canvas was not cleared, and the last frame already showed that
   * (the first still frame is drawn).
   * @param {boolean} moving
   */
  keepsLastFrame (moving) {
    const { renderer } = this.page
    const still = !moving && !renderer.busy && !renderer.needsDraw
    const keep = still && this.idleDrawn
    this.idleDrawn = still
    return keep
  }

  record (now, tick, poses, a, b) {
    let deviation = 0
    for (const pose of poses) deviation = Math.max(deviation, pose.deviation)
    this.trace.push({ now, tick, balls: poses.length, deviation, a: a ? a.tick : null, b: b ? b.tick : null })
  }

  /**
   * The peg hits and landings the view met since the last frame: their
   * sounds, glows and pops (`drawn`: the worker drew the glows and pops
   * already), and the results shown as balls land.
   */
  playEvents (view, now, { drawn = false } = {}) {
    const { renderer, sound } = this.page
    const rows = pegRowCount(view.board)
    for (const hit of view.pegHits) {
      if (!drawn) renderer.glowPeg(hit.peg, hit.mine, now)
      sound.pegTick(hit.row, rows, hit.mine)
    }
    view.pegHits.length = 0
    for (const landing of view.landings) this.onLanding(view, landing, now, drawn)
    view.landings.length = 0
  }

  /** A ball reached its bucket on screen (the local simulation's landing). */
  onLanding (view, landing, now, drawn = false) {
    const { renderer, sound, results } = this.page
    const multiplier = view.board.multipliers[landing.bucket]
    // Shown from now on (a room simulated in the worker reports its landings after it drew them).
    landing.drop.landingShown = true
    if (!landing.stale) {
      landing.drop.landedOnScreenAt = now
      if (!drawn) renderer.flash(landing.bucket, landing.mine, now)
      sound.landing(multiplier, landing.mine)
    }
    results.landed(landing)
  }

  updateFooter () {
    const { connection: { timeline: t, socket }, snapshotChecks } = this.page
    const parts = [`engine ${ENGINE_VERSION}`]
    if (socket.rttMs !== null) parts.push(`rtt ${Math.round(socket.rttMs)} ms`)
    if (t) parts.push(`buffer ${Math.round(t.delayMs)} ms (jitter ${Math.round(t.jitterMs)} ms)`)
    parts.push(`snapshot positions checked ${snapshotChecks.positions}${snapshotChecks.mismatches ? `, ${snapshotChecks.mismatches} OFF` : ''}`)
    byId('footer-stats').textContent = parts.join(' · ')
  }
}
