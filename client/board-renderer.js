import { LABEL_FORMS, labelText } from './bucket-labels.js'

/**
 * Draws a board and its balls on a canvas, at the device's pixel ratio,
 * scaled to fit its container (phone to desktop). Everything static — the
 * background, walls, pegs, buckets and their multipliers — is drawn once
 * into an offscreen layer when the board or the size changes; a frame is
 * that layer, the effects (peg glows, bucket bounces with their multiplier
 * popping, floating payouts, big-win bursts) and the balls with their trails.
 * Effects are started by the caller from what the local simulation says
 * happened (RoomView's peg hits and landings), never guessed.
 */

/**
 * Sizes of what is drawn around the physics, in units of 1/36 of a bucket's
 * width (board px on the 36 px buckets of engine 1.0.0), so every board,
 * whatever its scale, looks the same. Bucket boxes span from BUCKET_TOP
 * above the bucket line to `bucketBottom` below it (BUCKET_BOTTOM, or
 * deeper when the labels have to stand upright to stay readable on a
 * narrow screen); the view ends a little lower.
 */
const BUCKET_TOP = 4
const BUCKET_BOTTOM = 22
const VIEW_MARGIN_BOTTOM = 4
/**
 * Bucket labels are never drawn smaller than this (CSS px), from 320 to
 * 1920 px wide screens: a label that would be is written shorter, or the
 * labels stand upright in deeper buckets (resize, _labelLayout).
 */
export const MIN_LABEL_PX = 11
const LABEL_PX = 13
const UPRIGHT_LABEL_PX = 11
/**
 * Bucket depth (units) when the labels stand upright: fixed, so the board's
 * shape on a phone is known ahead (style.css reserves it before any script
 * runs); deep enough for the 16-row boards' labels without their × at
 * MIN_LABEL_PX on a 320 px screen ("0.52", "1k").
 */
export const UPRIGHT_BUCKET_BOTTOM = 72
const FLASH_MS = 520
const GLOW_MS = 320
const FLOAT_MS = 1300
const BURST_MS = 1700
const TRAIL_TICKS = 7
const MAX_PARTICLES = 240

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
    /** Bucket box depth below the bucket line, in drawing units. */
    this.bucketBottom = BUCKET_BOTTOM
    /**
     * How each bucket label was drawn (CSS px; boxes from the canvas's top left): its text's
     * size and length, the room for that length, its form (bucket-labels.js), the ink's box and its bucket's.
     * @type {{ text: string, px: number, width: number, room: number, upright: boolean, form: string, box: Box, bucket: Box }[]}
     */
    this.labels = []
    /** The labels' form (bucket-labels.js), and whether they all fit at MIN_LABEL_PX or more. */
    this.labelForm = 'full'
    this.labelsFit = true
    /** @type {{ bucket: number, mine: boolean, start: number }[]} */
    this.flashes = []
    /** @type {{ peg: number, mine: boolean, start: number }[]} */
    this.glows = []
    /** @type {{ text: string, x: number, y: number, start: number, big: boolean, color: string }[]} */
    this.floaters = []
    /** @type {{ x: number, y: number, vx: number, vy: number, color: string, start: number, size: number }[]} */
    this.particles = []
    /** @type {{ bucket: number, start: number }[]} */
    this.bursts = []
    /** Effects started so far, by kind (for tests and the curious). */
    /** floaterClearance: the least room (CSS px) between a floating payout and the bucket boxes below it, over every frame drawn (null: none yet) */
    this.effects = { pegGlows: 0, bucketPops: 0, floaters: 0, bursts: 0, trails: 0, floaterClearance: null }
    // prefers-reduced-motion: no glows, pops, floating payouts, bursts or trails (the balls and the board only).
    const reduce = typeof matchMedia === 'function' ? matchMedia('(prefers-reduced-motion: reduce)') : null
    this.reducedMotion = Boolean(reduce?.matches)
    reduce?.addEventListener('change', (event) => { this.reducedMotion = event.matches })
    /** @type {string[]} the texts of the floating payouts shown, latest last (at most 50) */
    this.floaterTexts = []
    this._colors = []
    /** @type {string[]} the label colour on each bucket (black or white: the one with more contrast) */
    this._textColors = []
    this.frames = 0
    /** Ball and glow sprites at the current size (made on the first frame after a resize). */
    this._sprites = null
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
    this.glows.length = 0
    this.floaters.length = 0
    this.particles.length = 0
    this.bursts.length = 0
    this._colors = bucketColors(board.multipliers)
    this._textColors = bucketTextColors(board.multipliers)
    this.resize()
  }

  /** The colour of each bucket of the current board (CSS). */
  get colors () {
    return this._colors
  }

  /** Height of the drawn world: the board and its bucket boxes. */
  get viewHeight () {
    return this.board ? this._viewHeightFor(this.bucketBottom) : 1
  }

  _viewHeightFor (bucketBottom) {
    return this.board.bucketLineY + (bucketBottom + VIEW_MARGIN_BOTTOM) * unitOf(this.board)
  }

  /** Anything still animating (the caller keeps drawing frames until it is not). */
  get busy () {
    return this.flashes.length > 0 || this.glows.length > 0 || this.floaters.length > 0 || this.particles.length > 0 || this.bursts.length > 0
  }

  resize () {
    const board = this.board
    const parent = this.canvas.parentElement
    if (!board || !parent) return
    const available = Math.max(160, parent.clientWidth)
    const tallest = Math.max(160, this.maxHeight())
    const scaleFor = (bucketBottom) => Math.min(available / board.width, tallest / this._viewHeightFor(bucketBottom))
    const { upright, form, fit } = this._labelLayout(scaleFor)
    const bucketBottom = upright ? UPRIGHT_BUCKET_BOTTOM : BUCKET_BOTTOM
    const scale = scaleFor(bucketBottom)
    const viewHeight = this._viewHeightFor(bucketBottom)
    const cssWidth = Math.floor(board.width * scale)
    const cssHeight = Math.floor(viewHeight * scale)
    const ratio = Math.min(3, window.devicePixelRatio || 1)
    // The page reserves the board's space with this (CSS), so nothing moves when the canvas is sized.
    parent.style.setProperty('--board-aspect', String(board.width / viewHeight))
    if (cssWidth === this._cssWidth && cssHeight === this._cssHeight && ratio === this.ratio && this.layer.width > 0 && this._layerBoard === board && form === this.labelForm) return
    this._cssWidth = cssWidth
    this._cssHeight = cssHeight
    this._layerBoard = board
    this.scale = scale
    this.ratio = ratio
    this.bucketBottom = bucketBottom
    this.upright = upright
    this.labelForm = form
    this.labelsFit = fit
    this.canvas.style.width = `${cssWidth}px`
    this.canvas.style.height = `${cssHeight}px`
    this.canvas.width = Math.round(cssWidth * ratio)
    this.canvas.height = Math.round(cssHeight * ratio)
    this.layer.width = this.canvas.width
    this.layer.height = this.canvas.height
    this._drawStatic()
    this._sprites = null
    this.needsDraw = true
    this.onResize()
  }

  /**
   * How the labels are laid out at the scales `scaleFor` gives: lying flat
   * if every one fits its bucket at MIN_LABEL_PX or more, else upright in
   * deeper buckets; in the plainest form that lets them (the sign dropped,
   * thousands in k, before the text is turned). Upright in the tightest form,
   * drawn smaller (fit false), only where nothing fits: a board far smaller
   * than a 320 px screen's.
   * @param {(bucketBottom: number) => number} scaleFor CSS px per board px
   */
  _labelLayout (scaleFor) {
    for (const upright of [false, true]) {
      const scale = scaleFor(upright ? UPRIGHT_BUCKET_BOTTOM : BUCKET_BOTTOM)
      const form = LABEL_FORMS.find((f) => (upright || f !== 'tight') && this._labelsFit(scale, upright, f))
      if (form) return { upright, form, fit: true }
    }
    return { upright: true, form: 'tight', fit: false }
  }

  /** Every label in `form` fits its bucket at MIN_LABEL_PX, lying flat or upright, at `scale`. */
  _labelsFit (scale, upright, form) {
    const { along, across } = this._labelRoom(scale, upright)
    if (across < MIN_LABEL_PX) return false
    const ctx = this.layer.getContext('2d')
    ctx.font = labelFont(MIN_LABEL_PX)
    return this.board.multipliers.every((m) => ctx.measureText(labelText(m, form)).width <= along)
  }

  /**
   * The room for a label at `scale` (CSS px): `along` its text, `across` it
   * (for the font's size). Flat: the bucket's width less a margin, across
   * the bucket's depth; upright: the deep bucket's depth less a margin,
   * across 90% of the bucket's width.
   */
  _labelRoom (scale, upright) {
    const u = unitOf(this.board)
    const width = (this.board.bucketWidth - 6 * u) * scale
    if (!upright) return { along: width, across: (BUCKET_TOP + BUCKET_BOTTOM - 4) * u * scale }
    return { along: (BUCKET_TOP + UPRIGHT_BUCKET_BOTTOM - 4) * u * scale, across: width * 0.9 }
  }

  /** A label's size (CSS px): as large as its room allows, LABEL_PX (flat) or UPRIGHT_LABEL_PX at most; MIN_LABEL_PX or more when the layout fits. */
  _labelPx (text, along, across) {
    const largest = this.upright ? UPRIGHT_LABEL_PX : LABEL_PX
    const ctx = this.layer.getContext('2d')
    ctx.font = labelFont(largest)
    const px = Math.min(largest, across, largest * along / ctx.measureText(text).width)
    // Widths grow with the size all but exactly: the layout measured the fit at MIN_LABEL_PX.
    return this.labelsFit ? Math.max(MIN_LABEL_PX, px) : px
  }

  /** Bounces bucket `bucket` and pops its multiplier. @param {number} bucket @param {boolean} mine @param {number} now */
  flash (bucket, mine, now) {
    if (this.reducedMotion) return
    this.flashes.push({ bucket, mine, start: now })
    this.effects.bucketPops++
  }

  /** A short glow on peg `peg` (index in board.pegs). @param {number} peg @param {boolean} mine @param {number} now */
  glowPeg (peg, mine, now) {
    if (this.reducedMotion) return
    const glow = this.glows.find((g) => g.peg === peg)
    if (glow) {
      glow.start = now
      glow.mine = glow.mine || mine
    } else {
      this.glows.push({ peg, mine, start: now })
    }
    this.effects.pegGlows++
  }

  /**
   * Floating text rising from a bucket ("+2,500").
   * @param {number} bucket @param {string} text @param {number} now @param {{ big?: boolean }} [options]
   */
  floatText (bucket, text, now, { big = false } = {}) {
    const board = this.board
    if (!board || this.reducedMotion) return
    const x = board.bucketLeftX + (bucket + 0.5) * board.bucketWidth
    this.floaters.push({ text, x, y: board.bucketLineY - 10 * unitOf(board), start: now, big, color: this._colors[bucket] ?? '#fff' })
    this.effects.floaters++
    this.floaterTexts.push(text)
    if (this.floaterTexts.length > 50) this.floaterTexts.shift()
  }

  /** A big win: sparks burst from the bucket and the board glows in its colour. @param {number} bucket @param {number} now */
  celebrate (bucket, now) {
    const board = this.board
    if (!board || this.reducedMotion) return
    const u = unitOf(board)
    const x = board.bucketLeftX + (bucket + 0.5) * board.bucketWidth
    const y = board.bucketLineY
    const palette = ['#ffd84d', '#ff5a8a', '#7cf2c9', '#ffffff', this._colors[bucket] ?? '#ffc400']
    for (let i = 0; i < 70 && this.particles.length < MAX_PARTICLES; i++) {
      const angle = -Math.PI / 2 + (Math.random() - 0.5) * Math.PI * 0.9
      const speed = (60 + Math.random() * 140) * u
      this.particles.push({ x, y, vx: Math.cos(angle) * speed, vy: Math.sin(angle) * speed, color: palette[i % palette.length], start: now, size: (2 + Math.random() * 3) * u })
    }
    this.bursts.push({ bucket, start: now })
    this.effects.bursts++
  }

  /**
   * One frame: the static layer, then the effects and the balls. Balls and
   * peg glows are sprites drawn once per size (_makeSprites), not a
   * radial gradient and an arc per ball per frame: in software rendering
   * (no GPU) a gradient fill is what costs. (Restoring only the parts the
   * last frame drew on, from the layer, measured slower than one copy of
   * the whole layer: a copy per ball costs more than the pixels saved.)
   * @param {import('./room-view.js').BallPose[]} poses
   * @param {number} now ms
   * @param {{ trail?: { trajectory: Float64Array, upto: number } }} [extra] a path to draw behind the balls (replays)
   */
  draw (poses, now, extra = {}) {
    const ctx = this.context
    const board = this.board
    if (!board || this.canvas.width === 0) return
    this.frames++
    const s = this.scale * this.ratio
    const u = unitOf(board)
    const trail = extra.trail
    this._sprites ??= this._makeSprites()
    this.needsDraw = false
    ctx.setTransform(1, 0, 0, 1, 0, 0)
    ctx.drawImage(this.layer, 0, 0)
    ctx.setTransform(s, 0, 0, s, 0, 0)

    this._drawBursts(ctx, now, u)
    this._drawGlows(ctx, now, u, s)
    this._drawFlashes(ctx, now, u, s)

    if (trail && trail.upto > 0) {
      ctx.strokeStyle = 'rgba(255, 196, 0, 0.55)'
      ctx.lineWidth = 1.5 * u
      ctx.beginPath()
      ctx.moveTo(trail.trajectory[0], trail.trajectory[1])
      for (let k = 3; k <= 3 * trail.upto; k += 3) ctx.lineTo(trail.trajectory[k], trail.trajectory[k + 1])
      ctx.stroke()
    }

    const r = board.ballRadius
    // Trails first, so no trail crosses a ball: the others', then the player's own on top.
    if (!this.reducedMotion) {
      ctx.lineCap = 'round'
      this._drawTrails(ctx, poses, false, 'rgba(150, 170, 230, 0.18)', r * 0.8)
      this._drawTrails(ctx, poses, true, 'rgba(255, 110, 150, 0.30)', r * 1.1)
    }
    const sprites = this._sprites
    ctx.strokeStyle = 'rgba(30, 20, 60, 0.55)'
    ctx.lineWidth = 1.4 * u
    for (const pose of poses) {
      ctx.globalAlpha = Math.max(0, Math.min(1, pose.alpha))
      // Own balls: a halo, and warm colours; the others' cool.
      const sprite = pose.mine ? sprites.mine : sprites.other
      const half = sprite.width / 2
      ctx.setTransform(1, 0, 0, 1, 0, 0)
      ctx.drawImage(sprite, Math.round(pose.x * s - half), Math.round(pose.y * s - half))
      ctx.setTransform(s, 0, 0, s, 0, 0)
      // A mark on the ball shows its spin.
      ctx.beginPath()
      ctx.moveTo(pose.x, pose.y)
      ctx.lineTo(pose.x + Math.cos(pose.angle) * r * 0.85, pose.y + Math.sin(pose.angle) * r * 0.85)
      ctx.stroke()
    }
    ctx.globalAlpha = 1

    this._drawParticles(ctx, now)
    this._drawFloaters(ctx, now, u, s)
    ctx.globalAlpha = 1
  }

  /**
   * The trails of the balls in flight that are the player's own (`mine`)
   * or not, as one path stroked once: a stroke per trail cost more than
   * everything else in a frame under software rendering; where two trails
   * of a kind cross, they no longer darken each other.
   */
  _drawTrails (ctx, poses, mine, color, width) {
    let drawn = 0
    ctx.beginPath()
    for (const pose of poses) {
      if (pose.mine !== mine || !pose.trajectory || pose.alpha < 1) continue
      const t = pose.trajectory
      const newest = Math.floor(pose.age)
      if (newest < 1) continue
      ctx.moveTo(pose.x, pose.y)
      for (let i = newest; i >= Math.max(0, newest - TRAIL_TICKS); i--) ctx.lineTo(t[3 * i] + pose.ox, t[3 * i + 1] + pose.oy)
      drawn++
    }
    if (drawn === 0) return
    ctx.strokeStyle = color
    ctx.lineWidth = width
    ctx.stroke()
    this.effects.trails += drawn
  }

  /**
   * The balls and the peg glows drawn once at this size (device px): an
   * own ball with its halo, another player's, and a glow of each kind at
   * its largest (drawn smaller as it grows, fainter as it fades).
   */
  _makeSprites () {
    const board = this.board
    const s = this.scale * this.ratio
    const r = board.ballRadius
    const sprite = (reach, paint) => {
      const canvas = document.createElement('canvas')
      const size = Math.ceil(2 * reach * s) + 4
      canvas.width = size
      canvas.height = size
      const ctx = canvas.getContext('2d')
      ctx.setTransform(s, 0, 0, s, size / 2, size / 2)
      paint(ctx)
      return canvas
    }
    const ball = (ctx, radius, inner, outer) => {
      const gradient = ctx.createRadialGradient(-r * 0.35, -r * 0.35, r * 0.15, 0, 0, r)
      gradient.addColorStop(0, inner)
      gradient.addColorStop(1, outer)
      ctx.fillStyle = gradient
      ctx.beginPath()
      ctx.arc(0, 0, radius, 0, Math.PI * 2)
      ctx.fill()
    }
    const glowReach = board.pegRadius + 8 * unitOf(board)
    const glow = (color) => sprite(glowReach, (ctx) => {
      const gradient = ctx.createRadialGradient(0, 0, board.pegRadius * 0.5, 0, 0, glowReach)
      gradient.addColorStop(0, color)
      gradient.addColorStop(1, 'rgba(255, 225, 120, 0)')
      ctx.fillStyle = gradient
      ctx.beginPath()
      ctx.arc(0, 0, glowReach, 0, Math.PI * 2)
      ctx.fill()
    })
    return {
      mine: sprite(r * 1.75, (ctx) => {
        ctx.fillStyle = 'rgba(255, 90, 138, 0.28)'
        ctx.beginPath()
        ctx.arc(0, 0, r * 1.75, 0, Math.PI * 2)
        ctx.fill()
        ball(ctx, r, '#fff3b0', '#ff5a8a')
      }),
      other: sprite(r, (ctx) => ball(ctx, r * 0.9, '#e9eeff', '#6f83b9')),
      glowMine: glow('rgba(255, 225, 120, 0.95)'),
      glowOther: glow('rgba(180, 205, 255, 0.7)'),
      glowReach
    }
  }

  _drawGlows (ctx, now, u, s) {
    const board = this.board
    const sprites = this._sprites
    this.glows = this.glows.filter((g) => now - g.start < GLOW_MS)
    for (const g of this.glows) {
      const peg = board.pegs[g.peg]
      if (!peg) continue
      const t = (now - g.start) / GLOW_MS
      const radius = board.pegRadius + (3 + 5 * t) * u
      const sprite = g.mine ? sprites.glowMine : sprites.glowOther
      // Half the sprite, in board px, scaled from its gradient's edge (glowReach) to this radius.
      const drawn = sprite.width / (2 * s) * radius / sprites.glowReach
      ctx.globalAlpha = 1 - t
      ctx.drawImage(sprite, peg.x - drawn, peg.y - drawn, 2 * drawn, 2 * drawn)
      ctx.fillStyle = '#ffffff'
      ctx.beginPath()
      ctx.arc(peg.x, peg.y, board.pegRadius * (1 + 0.35 * (1 - t)), 0, Math.PI * 2)
      ctx.fill()
    }
    ctx.globalAlpha = 1
  }

  _drawFlashes (ctx, now, u, s) {
    const board = this.board
    this.flashes = this.flashes.filter((f) => now - f.start < FLASH_MS)
    const height = (BUCKET_TOP + this.bucketBottom) * u
    for (const f of this.flashes) {
      const t = (now - f.start) / FLASH_MS
      const x = board.bucketLeftX + f.bucket * board.bucketWidth
      // The bucket dips and springs back; its label pops.
      const dip = 4 * Math.sin(Math.min(1, t * 1.6) * Math.PI) * (1 - t) * u
      const top = board.bucketLineY - BUCKET_TOP * u + dip
      ctx.globalAlpha = 1
      ctx.fillStyle = '#0b1024'
      ctx.fillRect(x + 1 * u, board.bucketLineY - BUCKET_TOP * u, board.bucketWidth - 2 * u, height + 5 * u)
      ctx.fillStyle = this._colors[f.bucket]
      roundRect(ctx, x + 2 * u, top, board.bucketWidth - 4 * u, height, 4 * u)
      ctx.fill()
      ctx.globalAlpha = (1 - t) * 0.7
      ctx.fillStyle = f.mine ? '#ffffff' : '#cfd8ff'
      roundRect(ctx, x + 2 * u, top, board.bucketWidth - 4 * u, height, 4 * u)
      ctx.fill()
      ctx.globalAlpha = 1
      const pop = 1 + 0.45 * Math.sin(Math.min(1, t * 2) * Math.PI)
      this._label(ctx, f.bucket, x + board.bucketWidth / 2, top + height / 2 + 0.5 * u, s, pop)
    }
    ctx.globalAlpha = 1
  }

  _drawFloaters (ctx, now, u, s) {
    this.floaters = this.floaters.filter((f) => now - f.start < FLOAT_MS)
    for (const f of this.floaters) {
      const t = (now - f.start) / FLOAT_MS
      const base = f.big ? 22 : 14
      const px = base * (1 + 0.15 * Math.sin(Math.min(1, t * 3) * Math.PI))
      ctx.font = `800 ${px / this.scale}px system-ui, sans-serif`
      ctx.textAlign = 'center'
      ctx.textBaseline = 'middle'
      const metrics = ctx.measureText(f.text)
      // Start with the text's lowest point (at its largest) clear of the bucket boxes, so it never covers their labels.
      const bucketTop = this.board.bucketLineY - BUCKET_TOP * u
      const stroke = 1.5 / this.scale
      const start = Math.min(f.y, bucketTop - 2 * u - metrics.actualBoundingBoxDescent * 1.15 * base / px - stroke)
      const y = start - (f.big ? 40 : 24) * u * easeOut(t)
      const clearance = (bucketTop - (y + metrics.actualBoundingBoxDescent + stroke)) * this.scale
      this.effects.floaterClearance = Math.min(this.effects.floaterClearance ?? Infinity, clearance)
      // Keep the text on the board.
      const half = metrics.width / 2
      const x = Math.max(half + 2 * u, Math.min(this.board.width - half - 2 * u, f.x))
      ctx.globalAlpha = t < 0.7 ? 1 : (1 - t) / 0.3
      ctx.lineWidth = 3 / this.scale
      ctx.strokeStyle = 'rgba(10, 8, 30, 0.85)'
      ctx.strokeText(f.text, x, y)
      ctx.fillStyle = f.big ? '#ffd84d' : '#7cf29a'
      ctx.fillText(f.text, x, y)
    }
    ctx.globalAlpha = 1
  }

  _drawBursts (ctx, now, u) {
    const board = this.board
    this.bursts = this.bursts.filter((b) => now - b.start < BURST_MS)
    for (const b of this.bursts) {
      const t = (now - b.start) / BURST_MS
      const x = board.bucketLeftX + (b.bucket + 0.5) * board.bucketWidth
      const radius = (40 + 260 * easeOut(t)) * u
      const glow = ctx.createRadialGradient(x, board.bucketLineY, 0, x, board.bucketLineY, radius)
      glow.addColorStop(0, 'rgba(255, 216, 77, 0.45)')
      glow.addColorStop(1, 'rgba(255, 90, 138, 0)')
      ctx.globalAlpha = 1 - t
      ctx.fillStyle = glow
      ctx.fillRect(0, 0, board.width, board.height + 20 * u)
    }
    ctx.globalAlpha = 1
  }

  _drawParticles (ctx, now) {
    const board = this.board
    const gravity = 980 * unitOf(board) / 4
    this.particles = this.particles.filter((p) => now - p.start < BURST_MS)
    for (const p of this.particles) {
      const t = (now - p.start) / 1000
      const x = p.x + p.vx * t
      const y = p.y + p.vy * t + 0.5 * gravity * t * t
      ctx.globalAlpha = Math.max(0, 1 - (now - p.start) / BURST_MS)
      ctx.fillStyle = p.color
      ctx.fillRect(x - p.size / 2, y - p.size / 2, p.size, p.size)
    }
    ctx.globalAlpha = 1
  }

  /** Bucket `i`'s multiplier centred at (x, y), flat or upright as the layout says, `pop` times its size. */
  _label (ctx, i, x, y, s, pop = 1) {
    const text = labelText(this.board.multipliers[i], this.labelForm)
    const scale = this.scale
    const { along, across } = this._labelRoom(scale, this.upright)
    const px = this._labelPx(text, along, across)
    ctx.save()
    ctx.fillStyle = this._textColors[i] ?? '#000'
    ctx.textAlign = 'center'
    ctx.textBaseline = 'middle'
    ctx.translate(x, y)
    if (this.upright) ctx.rotate(-Math.PI / 2)
    ctx.font = labelFont(px * pop / scale)
    ctx.fillText(text, 0, 0)
    if (pop === 1) {
      ctx.font = labelFont(px)
      const metrics = ctx.measureText(text)
      this.labels[i] = { text, px, width: metrics.width, room: along, upright: Boolean(this.upright), form: this.labelForm, box: this._inkBox(metrics, x * scale, y * scale), bucket: this._bucketBox(i), color: this._textColors[i], background: this._colors[i] }
    }
    ctx.restore()
  }

  /** Where a label's ink is (CSS px), centred at (cx, cy), turned a quarter left when upright. @returns {Box} */
  _inkBox (metrics, cx, cy) {
    const { actualBoundingBoxLeft: left, actualBoundingBoxRight: right, actualBoundingBoxAscent: ascent, actualBoundingBoxDescent: descent } = metrics
    if (this.upright) return { left: cx - ascent, right: cx + descent, top: cy - right, bottom: cy + left }
    return { left: cx - left, right: cx + right, top: cy - ascent, bottom: cy + descent }
  }

  /** Bucket `i`'s box as drawn (CSS px). @returns {Box} */
  _bucketBox (i) {
    const board = this.board
    const u = unitOf(board)
    const x = board.bucketLeftX + i * board.bucketWidth
    const top = board.bucketLineY - BUCKET_TOP * u
    const scale = this.scale
    return { left: (x + 2 * u) * scale, right: (x + board.bucketWidth - 2 * u) * scale, top: top * scale, bottom: (top + (BUCKET_TOP + this.bucketBottom) * u) * scale }
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
    const height = (BUCKET_TOP + this.bucketBottom) * u
    this.labels = []
    for (let i = 0; i < board.multipliers.length; i++) {
      const x = board.bucketLeftX + i * board.bucketWidth
      ctx.fillStyle = this._colors[i]
      roundRect(ctx, x + 2 * u, top, board.bucketWidth - 4 * u, height, 4 * u)
      ctx.fill()
      this._label(ctx, i, x + board.bucketWidth / 2, top + height / 2 + 0.5 * u, this.scale)
    }
  }
}

/** Each bucket's hue and lightness, from yellow (lowest multiplier) to red (highest), on a log scale. @param {number[]} multipliers */
function bucketHues (multipliers) {
  const logs = multipliers.map((m) => Math.log(m))
  const min = Math.min(...logs)
  const span = Math.max(1e-9, Math.max(...logs) - min)
  return logs.map((value) => {
    const t = (value - min) / span
    return { hue: Math.round(48 - 48 * t), lightness: Math.round(58 - 8 * t) }
  })
}

/** Bucket colours (CSS). @param {number[]} multipliers */
export function bucketColors (multipliers) {
  return bucketHues(multipliers).map(({ hue, lightness }) => `hsl(${hue}, 95%, ${lightness}%)`)
}

/**
 * The text colour for each bucket's colour: black or white, whichever
 * contrasts more (WCAG's relative luminance); on this palette either
 * reaches 5:1 or more, where the old dark ink had 4.35:1 on the reds.
 * @param {number[]} multipliers
 */
export function bucketTextColors (multipliers) {
  return bucketHues(multipliers).map(({ hue, lightness }) => {
    const l = relativeLuminance(hslToRgb(hue, 0.95, lightness / 100))
    return (l + 0.05) / 0.05 >= 1.05 / (l + 0.05) ? '#000' : '#fff'
  })
}

function hslToRgb (hue, saturation, lightness) {
  const a = saturation * Math.min(lightness, 1 - lightness)
  const channel = (n) => {
    const k = (n + hue / 30) % 12
    return lightness - a * Math.max(-1, Math.min(k - 3, 9 - k, 1))
  }
  return [channel(0), channel(8), channel(4)]
}

function relativeLuminance (rgb) {
  const [r, g, b] = rgb.map((c) => (c <= 0.03928 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4))
  return 0.2126 * r + 0.7152 * g + 0.0722 * b
}

/** @typedef {{ left: number, right: number, top: number, bottom: number }} Box */

function labelFont (px) {
  return `700 ${px}px system-ui, sans-serif`
}

function easeOut (t) {
  return 1 - (1 - t) * (1 - t)
}

function roundRect (ctx, x, y, width, height, radius) {
  ctx.beginPath()
  ctx.roundRect(x, y, width, height, radius)
}
