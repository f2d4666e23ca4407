/**
 * Plays a drop's trajectory (x, y, angle after every tick, from
 * simulateDrop(…, { trajectory: true })) on a BoardRenderer: play/pause,
 * step forward and back one tick, seek, and speed. Playback runs on
 * requestAnimationFrame at `speed` × 60 ticks per second, interpolating
 * between ticks, and stops at the landing.
 */
export class ReplayPlayer {
  /**
   * @param {import('./board-renderer.js').BoardRenderer} renderer
   * @param {(player: ReplayPlayer) => void} onChange called whenever the position or state changes
   */
  constructor (renderer, onChange) {
    this.renderer = renderer
    this.onChange = onChange
    /** @type {Float64Array | null} */
    this.trajectory = null
    this.ticks = 0
    this.position = 0
    this.speed = 1
    this.playing = false
    this.bucket = null
    this._lastFrame = null
    this._frame = (now) => this._advance(now)
  }

  /**
   * @param {import('/engine/board.js').Board} board
   * @param {Float64Array} trajectory
   * @param {number} bucket where it lands (lit at the end)
   */
  load (board, trajectory, bucket) {
    this.pause()
    this.trajectory = trajectory
    this.ticks = trajectory.length / 3 - 1
    this.bucket = bucket
    this.position = 0
    this.renderer.setBoard(board)
    this.render()
  }

  get tick () { return Math.floor(this.position) }

  play () {
    if (!this.trajectory || this.playing) return
    if (this.position >= this.ticks) this.position = 0
    this.playing = true
    this._lastFrame = null
    requestAnimationFrame(this._frame)
    this.onChange(this)
  }

  pause () {
    if (!this.playing) return
    this.playing = false
    this.onChange(this)
  }

  toggle () {
    if (this.playing) this.pause()
    else this.play()
  }

  /** @param {number} ticks forward (negative: back); pauses */
  step (ticks) {
    this.pause()
    this.seek(Math.round(this.position) + ticks)
  }

  /** @param {number} tick */
  seek (tick) {
    if (!this.trajectory) return
    this.position = Math.max(0, Math.min(this.ticks, tick))
    this.render()
  }

  /** @param {number} speed multiple of real time */
  setSpeed (speed) {
    this.speed = speed
    this.onChange(this)
  }

  _advance (now) {
    if (!this.playing) return
    if (this._lastFrame !== null) this.position += (now - this._lastFrame) / 1000 * 60 * this.speed
    this._lastFrame = now
    if (this.position >= this.ticks) {
      this.position = this.ticks
      this.playing = false
    }
    this.render(now)
    if (this.playing) requestAnimationFrame(this._frame)
  }

  render (now = performance.now()) {
    const t = this.trajectory
    if (!t) return
    const i = Math.floor(this.position)
    const f = this.position - i
    const k = 3 * i
    const n = i < this.ticks ? k + 3 : k
    const pose = {
      x: t[k] + (t[n] - t[k]) * f,
      y: t[k + 1] + (t[n + 1] - t[k + 1]) * f,
      angle: t[k + 2] + (t[n + 2] - t[k + 2]) * f,
      mine: true,
      alpha: 1,
      dropId: 0,
      deviation: 0
    }
    if (i >= this.ticks && this.bucket !== null && this.renderer.flashes.length === 0) this.renderer.flash(this.bucket, true, now)
    this.renderer.draw([pose], now, { trail: { trajectory: t, upto: i } })
    this.onChange(this)
  }
}
