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
   * @param {{ onDrawn: (stats: { trails: number, floaterClearance: number | null }) => void, onError: (error: unknown) => void }} handlers
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
    this.worker.onmessage = ({ data }) => {
      if (data.type === 'drawn') this._drawn(data)
      else if (data.type === 'pixels') {
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

  command (command) {
    this._commands.push(command)
  }

  /** @param {import('./room-view.js').BallPose[]} poses @param {number} now @param {boolean} reducedMotion @param {object} [trail] */
  frame (poses, now, reducedMotion, trail) {
    let commands = this._commands
    this._commands = []
    if (this._waiting) {
      commands = this._waiting.commands.concat(commands)
      this._spare.push(this._waiting.poses)
    }
    const buffer = this._buffer(poses.length)
    const count = packPoses(poses, buffer)
    const frame = { type: 'frame', poses: buffer, count, now, reducedMotion, trail, commands }
    if (this._inFlight) this._waiting = frame
    else this._post(frame)
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
    this.worker.postMessage(frame, [frame.poses.buffer])
  }

  _drawn ({ poses, stats }) {
    this._spare.push(poses)
    this._inFlight = false
    if (stats) this.onDrawn(stats)
    if (this._waiting) this._post(this._waiting)
  }

  /** A spare pose buffer with room for `count` balls (a new one if none has). */
  _buffer (count) {
    for (let i = 0; i < this._spare.length; i++) {
      if (this._spare[i].length >= count * STRIDE) return this._spare.splice(i, 1)[0]
    }
    return poseBuffer(count)
  }
}
