import { packPoses, poseBuffer, STRIDE } from './pose-frame.js'

/**
 * The page's side of the board drawn in a worker (board-worker.js): the
 * canvas is handed over once (transferControlToOffscreen), then each
 * frame goes as a small pose buffer (transferred, handed back with the
 * worker's answer and reused) with the effect commands started since the
 * last frame. One frame at most is with the worker: a frame asked for
 * while it draws waits, and a newer one replaces it (keeping its
 * commands), so a slow worker shows the latest balls, never a queue.
 * Same methods as the main-thread board (board-renderer.js's LocalBoard).
 */
export class WorkerBoard {
  /**
   * @param {HTMLCanvasElement} canvas not yet drawn on (it becomes the worker's)
   * @param {string | URL} url the worker script
   * @param {{ onDrawn: (stats: { trails: number, floaterClearance: number | null, frames?: number }) => void, onError: (error: unknown) => void }} handlers frames: how many frames the stats cover (1 if absent)
   */
  constructor (canvas, url, { onDrawn, onError }) {
    this.onDrawn = onDrawn
    this.worker = new Worker(url, { type: 'module' })
    const offscreen = canvas.transferControlToOffscreen()
    this.worker.postMessage({ type: 'canvas', canvas: offscreen }, [offscreen])
    /** @type {Float64Array[]} pose buffers back from the worker */
    this._spare = []
    /** @type {any[]} effect commands for the next frame */
    this._commands = []
    this._inFlight = false
    /** @type {any} the frame waiting for the worker */
    this._waiting = null
    /** @type {Map<number, (image: { width: number, height: number, data: Uint8ClampedArray }) => void>} */
    this._reads = new Map()
    this._nextRead = 1
    /** Seeds mode: the room simulated in the worker (its generation: reports of an older one are dropped) and who hears its reports. */
    this._seedsGeneration = 0
    /** @type {((report: import('./board-worker-room.js').FrameReport) => void) | null} */
    this._onSeeds = null
    /** prefers-reduced-motion, for the frames the worker draws on its own */
    this._reducedMotion = false
    this.worker.onmessage = ({ data }) => {
      if (data.type === 'drawn') this._drawn(data)
      else if (data.type === 'seeds-drawn') this._seedsDrawn(data.seeds)
      else if (data.type === 'pixels' || data.type === 'seeds-checked') {
        this._reads.get(data.id)?.(data)
        this._reads.delete(data.id)
      }
    }
    this.worker.onerror = (event) => onError(event)
  }

  /** @param {import('./board-painter.js').PaintLayout} layout */
  setLayout (layout) {
    this.worker.postMessage({ type: 'layout', layout })
  }

  /** A new board: effects started on the old one are dropped, sent or not. */
  clear () {
    this._commands = []
    if (this._waiting) this._waiting.commands = []
    this.worker.postMessage({ type: 'clear' })
  }

  /** An effect started: with the next frame, or at once where the worker draws a seeds room on its own. */
  command (command) {
    if (this._onSeeds !== null) this.worker.postMessage({ type: 'commands', commands: [command] })
    else this._commands.push(command)
  }

  /** @param {boolean} reduced prefers-reduced-motion */
  motion (reduced) {
    this._reducedMotion = reduced
    this.worker.postMessage({ type: 'motion', reduced })
  }

  /** @param {import('./room-view.js').BallPose[]} poses @param {number} now @param {boolean} reducedMotion @param {object} [trail] */
  frame (poses, now, reducedMotion, trail) {
    const commands = this._takeCommands()
    const buffer = this._buffer(poses.length)
    const count = packPoses(poses, buffer)
    this._queue({ type: 'frame', poses: buffer, count, now, reducedMotion, trail, commands })
  }

  /** The commands started since the last frame, with those of a frame that waits (it is replaced). */
  _takeCommands () {
    const commands = this._commands
    this._commands = []
    if (!this._waiting) return commands
    if (this._waiting.poses) this._spare.push(this._waiting.poses)
    const waiting = this._waiting.commands
    this._waiting = null
    return waiting.concat(commands)
  }

  /** Posts the frame, or keeps it as the one that waits for the worker's answer. */
  _queue (frame) {
    if (this._inFlight) this._waiting = frame
    else this._post(frame)
  }

  /**
   * Seeds mode: the joined room is simulated and drawn in the worker from
   * now on, on the worker's own animation frames (board-worker-room.js
   * drive()), replacing any room it had; `onReport` hears its reports.
   * @param {{ room: string, rows: number, risk: string, engineVersion: string }} spec
   * @param {(report: import('./board-worker-room.js').FrameReport) => void} onReport
   */
  openSeedsRoom (spec, onReport) {
    this._seedsGeneration++
    this._onSeeds = onReport
    for (const command of this._takeCommands()) this.worker.postMessage({ type: 'commands', commands: [command] })
    this.worker.postMessage({ type: 'seeds-open', generation: this._seedsGeneration, pageTimeOrigin: performance.timeOrigin, reducedMotion: this._reducedMotion, ...spec })
  }

  /** The room clock's line moved (room-clock.js): the worker's render tick follows it. @param {import('./room-clock.js').ClockLine | null} line */
  seedsClock (line) {
    this.worker.postMessage({ type: 'seeds-clock', line })
  }

  /** No room simulated in the worker any more. */
  closeSeedsRoom () {
    if (this._onSeeds === null) return
    this._seedsGeneration++
    this._onSeeds = null
    this.worker.postMessage({ type: 'seeds-close' })
  }

  /** @param {import('./board-worker-room.js').WorkerDrop} drop */
  seedsAdd (drop) { this.worker.postMessage({ type: 'seeds-add', drop }) }

  /** @param {number} dropId */
  seedsComplete (dropId) { this.worker.postMessage({ type: 'seeds-complete', dropId }) }

  /** @param {boolean} on */
  seedsTrace (on) { this.worker.postMessage({ type: 'seeds-trace', on }) }

  /**
   * The desync check, run where the room is simulated.
   * @param {number} tick @param {string} hash
   * @returns {Promise<{ ok: boolean, tick: number, server: string, local: string, balls: number } | null>} null: that room is not simulated there any more
   */
  seedsCheck (tick, hash) {
    const id = this._nextRead++
    return new Promise((resolve) => {
      this._reads.set(id, (data) => resolve(data.result))
      this.worker.postMessage({ type: 'seeds-check', id, generation: this._seedsGeneration, tick, hash })
    })
  }

  /** The canvas's pixels, read in the worker (for tests). */
  pixels () {
    const id = this._nextRead++
    return new Promise((resolve) => {
      this._reads.set(id, resolve)
      this.worker.postMessage({ type: 'pixels', id })
    })
  }

  _post (frame) {
    this._inFlight = true
    this._waiting = null
    this.worker.postMessage(frame, frame.poses ? [frame.poses.buffer] : [])
  }

  _drawn ({ poses, stats }) {
    if (poses) this._spare.push(poses)
    this._inFlight = false
    if (stats) this.onDrawn(stats)
    if (this._waiting) this._post(this._waiting)
  }

  /** The frames the worker drew on its own since its last report (a room opened since: dropped). @param {import('./board-worker-room.js').DrivenReport & { generation: number }} seeds */
  _seedsDrawn (seeds) {
    if (seeds.generation !== this._seedsGeneration) return
    const { frames, trails, floaterClearance } = seeds.drawn
    if (frames > 0) this.onDrawn({ trails, floaterClearance, frames })
    this._onSeeds?.(seeds)
  }

  /** A spare pose buffer with room for `count` balls (a new one if none has). */
  _buffer (count) {
    for (let i = 0; i < this._spare.length; i++) {
      if (this._spare[i].length >= count * STRIDE) return this._spare.splice(i, 1)[0]
    }
    return poseBuffer(count)
  }
}
