import { LABEL_FORMS, labelText } from './bucket-labels.js'
import { BUCKET_TOP, BUCKET_BOTTOM, VIEW_MARGIN_BOTTOM, MIN_LABEL_PX, LABEL_PX, UPRIGHT_LABEL_PX, UPRIGHT_BUCKET_BOTTOM, unitOf, labelFont, makeCanvas } from './board-geometry.js'
import { BoardPainter, paintedBoard, FLASH_MS, GLOW_MS, FLOAT_MS, BURST_MS } from './board-painter.js'
import { WorkerBoard } from './board-worker-client.js'
import { packPoses, poseBuffer, STRIDE } from './pose-frame.js'

export { MIN_LABEL_PX, UPRIGHT_BUCKET_BOTTOM }

/**
 * A board and its balls on a canvas, at the device's pixel ratio, scaled
 * to fit its container (phone to desktop). This is the main thread's side:
 * the layout (size, scale, how the bucket labels fit and where they are),
 * the effects started (counted, for tests and the curious) and the frames
 * drawn. The drawing itself is board-painter.js's, in a worker on an
 * OffscreenCanvas when the caller asks for it and the browser can
 * (board-worker-client.js: rasterising leaves the main thread), else on
 * the canvas here (LocalBoard), by the same code. Effects are started by
 * the caller from what the local simulation says happened (RoomView's peg
 * hits and landings), never guessed.
 */
export class BoardRenderer {
  /**
   * @param {HTMLCanvasElement} canvas
   * @param {{ maxHeight?: () => number, onResize?: () => void, worker?: string | URL | null }} [options] maxHeight: the tallest
   *   the canvas may be, in CSS px; onResize: the canvas was cleared by a resize (redraw it);
   *   worker: board-worker.js's URL, to draw there where OffscreenCanvas allows
   */
  constructor (canvas, { maxHeight = () => window.innerHeight * 0.72, onResize = () => {}, worker = null } = {}) {
    this.canvas = canvas
    this.maxHeight = maxHeight
    this.onResize = onResize
    /** The canvas was cleared (resized) since the last frame. */
    this.needsDraw = true
    /** @type {import('/engine/board.js').Board | null} */
    this.board = null
    this.scale = 1
    this.ratio = 1
    /** Bucket box depth below the bucket line, in drawing units. */
    this.bucketBottom = BUCKET_BOTTOM
    /**
     * How each bucket label is drawn (CSS px; boxes from the canvas's top left): its text's
     * size and length, the room for that length, its form (bucket-labels.js), the ink's box and its bucket's.
     * @type {{ text: string, px: number, width: number, room: number, upright: boolean, form: string, box: Box, bucket: Box }[]}
     */
    this.labels = []
    /** The labels' form (bucket-labels.js), and whether they all fit at MIN_LABEL_PX or more. */
    this.labelForm = 'full'
    this.labelsFit = true
    /** Bucket pops and floating payouts still showing (as of the last frame). */
    /** @type {{ bucket: number, mine: boolean, start: number }[]} */
    this.flashes = []
    /** @type {{ text: string, start: number }[]} */
    this.floaters = []
    /** When the last effect started ends, and the time of the last frame (ms). */
    this._busyUntil = -Infinity
    this._drawnAt = -Infinity
    /** Effects started so far, by kind (for tests and the curious). */
    /** floaterClearance: the least room (CSS px) between a floating payout and the bucket boxes below it, over every frame drawn (null: none yet) */
    this.effects = { pegGlows: 0, bucketPops: 0, floaters: 0, bursts: 0, trails: 0, floaterClearance: null }
    // prefers-reduced-motion: no glows, pops, floating payouts, bursts or trails (the balls and the board only).
    const reduce = typeof matchMedia === 'function' ? matchMedia('(prefers-reduced-motion: reduce)') : null
    this.reducedMotion = Boolean(reduce?.matches)
    reduce?.addEventListener('change', (event) => {
      this.reducedMotion = event.matches
      this.worker?.motion(event.matches)
    })
    /** @type {string[]} the texts of the floating payouts shown, latest last (at most 50) */
    this.floaterTexts = []
    this._colors = []
    /** @type {string[]} the label colour on each bucket (black or white: the one with more contrast) */
    this._textColors = []
    /** Frames drawn (by the worker: those it answered). */
    this.frames = 0
    /** Where labels are measured: the same fonts as the drawing, on the main thread. */
    this._measure = makeCanvas(1, 1).getContext('2d')
    this._measure.textAlign = 'center'
    this._measure.textBaseline = 'middle'
    const onDrawn = (stats) => this._drawn(stats)
    /** Where the board is drawn: 'worker' or 'main'. */
    this.drawnIn = 'main'
    /** Called once the worker failed and the board is drawn here instead (a room simulated there must start again here). */
    this.onFallBack = () => {}
    /** @type {LocalBoard | WorkerBoard} */
    this.target = null
    if (worker && canDrawInWorker(canvas)) {
      this.target = new WorkerBoard(canvas, worker, { onDrawn, onError: (error) => this._fallBack(error) })
      this.target.motion(this.reducedMotion)
      this.drawnIn = 'worker'
    } else {
      this.target = new LocalBoard(canvas, onDrawn)
    }
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

  /**
   * The worker could not start (its script blocked or missing) or failed:
   * a fresh canvas in the old one's place (that one is the worker's for
   * good), drawn on the main thread from now on.
   */
  _fallBack (error) {
    if (this.drawnIn !== 'worker') return
    console.warn('board worker failed; drawing on the main thread', error?.message ?? error)
    this.target.worker.terminate()
    const fresh = /** @type {HTMLCanvasElement} */ (this.canvas.cloneNode(false))
    this.canvas.replaceWith(fresh)
    this.canvas = fresh
    this.target = new LocalBoard(fresh, (stats) => this._drawn(stats))
    this.drawnIn = 'main'
    this._laidOut = null
    this.resize()
    this.onFallBack()
  }

  /** @param {import('/engine/board.js').Board} board */
  setBoard (board) {
    this.board = board
    this.flashes.length = 0
    this.floaters.length = 0
    this._busyUntil = -Infinity
    this._colors = bucketColors(board.multipliers)
    this._textColors = bucketTextColors(board.multipliers)
    this.target.clear()
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

  /** Floating payouts still showing now, wherever the frames are drawn (the board worker draws a seeds room's on its own). */
  get floating () {
    const now = performance.now()
    let count = 0
    for (const f of this.floaters) if (now - f.start < FLOAT_MS) count++
    return count
  }

  /** Anything still animating (the caller keeps drawing frames until it is not). */
  get busy () {
    return this._busyUntil > this._drawnAt
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
    const laidOut = `${cssWidth}×${cssHeight}@${ratio}:${form}`
    if (laidOut === this._laidOut && this._layoutBoard === board) return
    this._laidOut = laidOut
    this._layoutBoard = board
    this.scale = scale
    this.ratio = ratio
    this.bucketBottom = bucketBottom
    this.upright = upright
    this.labelForm = form
    this.labelsFit = fit
    this.canvas.style.width = `${cssWidth}px`
    this.canvas.style.height = `${cssHeight}px`
    this._layOutLabels()
    this.target.setLayout({
      board: paintedBoard(board),
      width: Math.round(cssWidth * ratio),
      height: Math.round(cssHeight * ratio),
      scale,
      ratio,
      bucketBottom,
      upright,
      labels: this.labels.map(({ text, px }) => ({ text, px })),
      colors: this._colors,
      textColors: this._textColors
    })
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
    const ctx = this._measure
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
    const ctx = this._measure
    ctx.font = labelFont(largest)
    const px = Math.min(largest, across, largest * along / ctx.measureText(text).width)
    // Widths grow with the size all but exactly: the layout measured the fit at MIN_LABEL_PX.
    return this.labelsFit ? Math.max(MIN_LABEL_PX, px) : px
  }

  /** Each bucket's label: its text and size, and where its ink and its bucket are (measured here, drawn by the painter at the same place). */
  _layOutLabels () {
    const board = this.board
    const u = unitOf(board)
    const scale = this.scale
    const { along, across } = this._labelRoom(scale, this.upright)
    const top = board.bucketLineY - BUCKET_TOP * u
    const height = (BUCKET_TOP + this.bucketBottom) * u
    const ctx = this._measure
    this.labels = board.multipliers.map((multiplier, i) => {
      const text = labelText(multiplier, this.labelForm)
      const px = this._labelPx(text, along, across)
      // The label's centre, as board-painter.js draws it.
      const x = board.bucketLeftX + (i + 0.5) * board.bucketWidth
      const y = top + height / 2 + 0.5 * u
      ctx.font = labelFont(px)
      const metrics = ctx.measureText(text)
      return { text, px, width: metrics.width, room: along, upright: Boolean(this.upright), form: this.labelForm, box: this._inkBox(metrics, x * scale, y * scale), bucket: this._bucketBox(i), color: this._textColors[i], background: this._colors[i] }
    })
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

  /** Bounces bucket `bucket` and pops its multiplier. @param {number} bucket @param {boolean} mine @param {number} now */
  flash (bucket, mine, now) {
    if (this.reducedMotion) return
    this.flashes.push({ bucket, mine, start: now })
    this._busy(now + FLASH_MS)
    this.effects.bucketPops++
    this.target.command(['flash', bucket, mine, now])
  }

  /** A short glow on peg `peg` (index in board.pegs). @param {number} peg @param {boolean} mine @param {number} now */
  glowPeg (peg, mine, now) {
    if (this.reducedMotion) return
    this._busy(now + GLOW_MS)
    this.effects.pegGlows++
    this.target.command(['glow', peg, mine, now])
  }

  /**
   * Floating text rising from a bucket ("+2,500").
   * @param {number} bucket @param {string} text @param {number} now @param {{ big?: boolean }} [options]
   */
  floatText (bucket, text, now, { big = false } = {}) {
    if (!this.board || this.reducedMotion) return
    // Those that ended go (frames drawn in the worker do not drop them here).
    this.floaters = this.floaters.filter((f) => now - f.start < FLOAT_MS)
    this.floaters.push({ text, start: now })
    this._busy(now + FLOAT_MS)
    this.effects.floaters++
    this.floaterTexts.push(text)
    if (this.floaterTexts.length > 50) this.floaterTexts.shift()
    this.target.command(['float', bucket, text, now, big])
  }

  /** A big win: sparks burst from the bucket and the board glows in its colour. @param {number} bucket @param {number} now */
  celebrate (bucket, now) {
    if (!this.board || this.reducedMotion) return
    this._busy(now + BURST_MS)
    this.effects.bursts++
    this.target.command(['celebrate', bucket, now])
  }

  _busy (until) {
    if (until > this._busyUntil) this._busyUntil = until
  }

  /**
   * One frame: the balls at `now` with the effects started so far (drawn
   * here or in the worker, board-painter.js).
   * @param {import('./room-view.js').BallPose[]} poses
   * @param {number} now ms
   * @param {{ trail?: { trajectory: Float64Array, upto: number } }} [extra] a path to draw behind the balls (replays)
   */
  draw (poses, now, extra = {}) {
    if (this._startFrame(now)) this.target.frame(poses, now, this.reducedMotion, extra.trail)
  }

  /**
   * Counts the effects the board worker started itself, for a room it
   * simulates and draws on its own frames (board-worker-room.js drive()).
   * @param {{ pegGlows: number, bucketPops: number }} drawn
   */
  countDrawnEffects ({ pegGlows, bucketPops }) {
    this.effects.pegGlows += pegGlows
    this.effects.bucketPops += bucketPops
  }

  /** The board where a seeds room can be simulated beside its drawing, or null (drawn on the main thread). */
  get worker () {
    return this.target instanceof WorkerBoard ? this.target : null
  }

  /** Whether a frame can be drawn now (a board laid out); the effects that ended are dropped. */
  _startFrame (now) {
    if (!this.board || this._laidOut === undefined || this._laidOut === null) return false
    this.needsDraw = false
    this._drawnAt = now
    this.flashes = this.flashes.filter((f) => now - f.start < FLASH_MS)
    this.floaters = this.floaters.filter((f) => now - f.start < FLOAT_MS)
    return true
  }

  /** A frame was drawn (here or in the worker): what it drew. */
  _drawn ({ trails, floaterClearance, frames = 1 }) {
    this.frames += frames
    this.effects.trails += trails
    if (floaterClearance !== null) this.effects.floaterClearance = Math.min(this.effects.floaterClearance ?? Infinity, floaterClearance)
  }

  /** The canvas's pixels as drawn (for tests: a canvas handed to a worker cannot be read here). @returns {Promise<{ width: number, height: number, data: Uint8ClampedArray }>} */
  pixels () {
    return this.target.pixels()
  }
}

/** The board drawn on the page's canvas, on the main thread: the painter called directly. */
class LocalBoard {
  /** @param {HTMLCanvasElement} canvas @param {(stats: { trails: number, floaterClearance: number | null }) => void} onDrawn */
  constructor (canvas, onDrawn) {
    this.painter = new BoardPainter(canvas)
    this.onDrawn = onDrawn
    this._poses = poseBuffer(0)
  }

  setLayout (layout) { this.painter.setLayout(layout) }
  clear () { this.painter.clearEffects() }
  command (command) { this.painter.apply(command) }

  frame (poses, now, reducedMotion, trail) {
    if (this._poses.length < poses.length * STRIDE) this._poses = poseBuffer(poses.length)
    const count = packPoses(poses, this._poses)
    const stats = this.painter.draw({ poses: this._poses, count, now, reducedMotion, trail })
    if (stats) this.onDrawn(stats)
  }

  pixels () {
    const { canvas, context } = this.painter
    return Promise.resolve({ width: canvas.width, height: canvas.height, data: context.getImageData(0, 0, canvas.width, canvas.height).data })
  }
}

/** The browser can hand this canvas to a worker (OffscreenCanvas and module workers). */
function canDrawInWorker (canvas) {
  return typeof canvas.transferControlToOffscreen === 'function' && typeof OffscreenCanvas === 'function' && typeof Worker === 'function'
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
