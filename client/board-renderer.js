import { formatMultiplier } from './dom.js'

/**
 * Draws a board and its balls on a canvas, at the device's pixel ratio,
 * scaled to fit its container (phone to desktop). Everything static — the
 * background, walls, pegs, buckets and their multipliers — is drawn once
 * into an offscreen layer when the board or the size changes; a frame is
 * that layer, the bucket flashes and the balls.
 */

/**
 * Sizes of what is drawn around the physics, in units of 1/36 of a bucket's
 * width (board px on the 36 px buckets of engine 1.0.0), so every board,
 * whatever its scale, looks the same. Bucket boxes span from BUCKET_TOP
 * above the bucket line to BUCKET_BOTTOM below it; the view ends a little lower.
 */
const BUCKET_TOP = 4
const BUCKET_BOTTOM = 22
const VIEW_MARGIN_BOTTOM = 4
const FLASH_MS = 450

/** Board px per drawing unit on `board`. @param {{ bucketWidth: number }} board */
function unitOf (board) {
  return board.bucketWidth / 36
}

export class BoardRenderer {
  /**
   * @param {HTMLCanvasElement} canvas
   * @param {{ maxHeight?: () => number, onResize?: () => void }} [options] maxHeight: the tallest
   *   the canvas may be, in CSS px; onResize: the canvas was cleared by a resize (redraw it)
   */
  constructor (canvas, { maxHeight = () => window.innerHeight * 0.72, onResize = () => {} } = {}) {
    this.canvas = canvas
    this.context = canvas.getContext('2d', { alpha: false })
    this.maxHeight = maxHeight
    this.onResize = onResize
    /** The canvas was cleared (resized) since the last frame. */
    this.needsDraw = true
    /** @type {import('/engine/board.js').Board | null} */
    this.board = null
    this.layer = document.createElement('canvas')
    this.scale = 1
    this.ratio = 1
    /** @type {{ bucket: number, mine: boolean, start: number }[]} */
    this.flashes = []
    this._colors = []
    this.frames = 0
    // Resizing the canvas resizes its container: do it on the next frame,
    // outside the observer's callback, so the observer never loops.
    this._resizeQueued = false
    const queueResize = () => {
      if (this._resizeQueued) return
      this._resizeQueued = true
      requestAnimationFrame(() => { this._resizeQueued = false; this.resize() })
    }
    this._observer = new ResizeObserver(queueResize)
    if (canvas.parentElement) this._observer.observe(canvas.parentElement)
    window.addEventListener('resize', queueResize)
  }

  /** @param {import('/engine/board.js').Board} board */
  setBoard (board) {
    this.board = board
    this.flashes.length = 0
    this._colors = bucketColors(board.multipliers)
    this.resize()
  }

  /** Height of the drawn world: the board and its bucket boxes. */
  get viewHeight () {
    return this.board ? this.board.bucketLineY + (BUCKET_BOTTOM + VIEW_MARGIN_BOTTOM) * unitOf(this.board) : 1
  }

  resize () {
    const board = this.board
    const parent = this.canvas.parentElement
    if (!board || !parent) return
    const available = Math.max(160, parent.clientWidth)
    const scale = Math.min(available / board.width, Math.max(160, this.maxHeight()) / this.viewHeight)
    const cssWidth = Math.floor(board.width * scale)
    const cssHeight = Math.floor(this.viewHeight * scale)
    const ratio = Math.min(3, window.devicePixelRatio || 1)
    if (cssWidth === this._cssWidth && cssHeight === this._cssHeight && ratio === this.ratio && this.layer.width > 0 && this._layerBoard === board) return
    this._cssWidth = cssWidth
    this._cssHeight = cssHeight
    this._layerBoard = board
    this.scale = scale
    this.ratio = ratio
    this.canvas.style.width = `${cssWidth}px`
    this.canvas.style.height = `${cssHeight}px`
    this.canvas.width = Math.round(cssWidth * ratio)
    this.canvas.height = Math.round(cssHeight * ratio)
    this.layer.width = this.canvas.width
    this.layer.height = this.canvas.height
    this._drawStatic()
    this.needsDraw = true
    this.onResize()
  }

  /** Lights bucket `bucket` for a moment. @param {number} bucket @param {boolean} mine @param {number} now */
  flash (bucket, mine, now) {
    this.flashes.push({ bucket, mine, start: now })
  }

  /**
   * One frame.
   * @param {import('./room-view.js').BallPose[]} poses
   * @param {number} now ms
   * @param {{ trail?: { trajectory: Float64Array, upto: number } }} [extra] a path to draw behind the balls (replays)
   */
  draw (poses, now, extra = {}) {
    const ctx = this.context
    const board = this.board
    if (!board || this.canvas.width === 0) return
    this.frames++
    this.needsDraw = false
    ctx.setTransform(1, 0, 0, 1, 0, 0)
    ctx.drawImage(this.layer, 0, 0)
    const s = this.scale * this.ratio
    const u = unitOf(board)
    ctx.setTransform(s, 0, 0, s, 0, 0)

    this.flashes = this.flashes.filter((f) => now - f.start < FLASH_MS)
    for (const f of this.flashes) {
      const t = (now - f.start) / FLASH_MS
      const x = board.bucketLeftX + f.bucket * board.bucketWidth
      ctx.globalAlpha = (1 - t) * 0.85
      ctx.fillStyle = f.mine ? '#ffffff' : '#cfd8ff'
      roundRect(ctx, x + 2 * u, board.bucketLineY + (3 * Math.sin(t * Math.PI) - BUCKET_TOP) * u, board.bucketWidth - 4 * u, (BUCKET_TOP + BUCKET_BOTTOM) * u, 4 * u)
      ctx.fill()
    }
    ctx.globalAlpha = 1

    const trail = extra.trail
    if (trail && trail.upto > 0) {
      ctx.strokeStyle = 'rgba(255, 196, 0, 0.55)'
      ctx.lineWidth = 1.5 * u
      ctx.beginPath()
      ctx.moveTo(trail.trajectory[0], trail.trajectory[1])
      for (let k = 3; k <= 3 * trail.upto; k += 3) ctx.lineTo(trail.trajectory[k], trail.trajectory[k + 1])
      ctx.stroke()
    }

    const r = board.ballRadius
    for (const pose of poses) {
      ctx.globalAlpha = Math.max(0, Math.min(1, pose.alpha))
      const gradient = ctx.createRadialGradient(pose.x - r * 0.35, pose.y - r * 0.35, r * 0.15, pose.x, pose.y, r)
      if (pose.mine) {
        gradient.addColorStop(0, '#fff3b0')
        gradient.addColorStop(1, '#ff5a8a')
      } else {
        gradient.addColorStop(0, '#ffffff')
        gradient.addColorStop(1, '#7f93c9')
      }
      ctx.fillStyle = gradient
      ctx.beginPath()
      ctx.arc(pose.x, pose.y, r, 0, Math.PI * 2)
      ctx.fill()
      // A mark on the ball shows its spin.
      ctx.strokeStyle = 'rgba(30, 20, 60, 0.55)'
      ctx.lineWidth = 1.4 * u
      ctx.beginPath()
      ctx.moveTo(pose.x, pose.y)
      ctx.lineTo(pose.x + Math.cos(pose.angle) * r * 0.85, pose.y + Math.sin(pose.angle) * r * 0.85)
      ctx.stroke()
    }
    ctx.globalAlpha = 1
  }

  _drawStatic () {
    const board = this.board
    const ctx = this.layer.getContext('2d', { alpha: false })
    const s = this.scale * this.ratio
    const u = unitOf(board)
    ctx.setTransform(1, 0, 0, 1, 0, 0)
    const background = ctx.createLinearGradient(0, 0, 0, this.layer.height)
    background.addColorStop(0, '#141b3a')
    background.addColorStop(1, '#0b1024')
    ctx.fillStyle = background
    ctx.fillRect(0, 0, this.layer.width, this.layer.height)
    ctx.setTransform(s, 0, 0, s, 0, 0)

    // Drop zone.
    const zone = board.dropZone
    ctx.fillStyle = 'rgba(255, 90, 138, 0.25)'
    roundRect(ctx, zone.minX - board.ballRadius, zone.y - board.ballRadius - 3 * u, zone.maxX - zone.minX + 2 * board.ballRadius, 2 * board.ballRadius + 6 * u, board.ballRadius + 3 * u)
    ctx.fill()

    ctx.strokeStyle = 'rgba(140, 160, 230, 0.35)'
    ctx.lineWidth = 2 * u
    ctx.lineCap = 'round'
    for (const [x1, y1, x2, y2] of board.walls) {
      ctx.beginPath()
      ctx.moveTo(x1, y1)
      ctx.lineTo(x2, y2)
      ctx.stroke()
    }

    for (const peg of board.pegs) {
      ctx.fillStyle = 'rgba(255, 255, 255, 0.12)'
      ctx.beginPath()
      ctx.arc(peg.x, peg.y, board.pegRadius + 2 * u, 0, Math.PI * 2)
      ctx.fill()
      ctx.fillStyle = '#e8ecff'
      ctx.beginPath()
      ctx.arc(peg.x, peg.y, board.pegRadius, 0, Math.PI * 2)
      ctx.fill()
    }

    const top = board.bucketLineY - BUCKET_TOP * u
    const height = (BUCKET_TOP + BUCKET_BOTTOM) * u
    for (let i = 0; i < board.multipliers.length; i++) {
      const x = board.bucketLeftX + i * board.bucketWidth
      ctx.fillStyle = this._colors[i]
      roundRect(ctx, x + 2 * u, top, board.bucketWidth - 4 * u, height, 4 * u)
      ctx.fill()
      fitText(ctx, formatMultiplier(board.multipliers[i]), x + board.bucketWidth / 2, top + height / 2 + 0.5 * u, board.bucketWidth - 6 * u, s, u)
    }
  }
}

/** Bucket colours from yellow (lowest multiplier) to red (highest), on a log scale. */
function bucketColors (multipliers) {
  const logs = multipliers.map((m) => Math.log(m))
  const min = Math.min(...logs)
  const span = Math.max(1e-9, Math.max(...logs) - min)
  return logs.map((value) => {
    const t = (value - min) / span
    return `hsl(${Math.round(48 - 48 * t)}, 95%, ${Math.round(58 - 8 * t)}%)`
  })
}

/** Centred text shrunk to fit `maxWidth` (board units), at least ~7 device px tall. */
function fitText (ctx, text, x, y, maxWidth, scale, unit) {
  let size = 11 * unit
  ctx.font = `700 ${size}px system-ui, sans-serif`
  const width = ctx.measureText(text).width
  if (width > maxWidth) size = Math.max(7 / scale, size * maxWidth / width)
  ctx.font = `700 ${size}px system-ui, sans-serif`
  ctx.fillStyle = '#1a1030'
  ctx.textAlign = 'center'
  ctx.textBaseline = 'middle'
  ctx.fillText(text, x, y)
}

function roundRect (ctx, x, y, width, height, radius) {
  ctx.beginPath()
  ctx.roundRect(x, y, width, height, radius)
}
