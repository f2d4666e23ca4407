import { BUCKET_TOP, unitOf, labelFont, makeCanvas } from './board-geometry.js'
import { STRIDE } from './pose-frame.js'

/**
 * The board's drawing: the one code that puts pixels on the board's
 * canvas, whether that canvas is on the page (the main thread draws) or
 * an OffscreenCanvas in a worker (board-worker.js). It only draws: the
 * layout (size, scale, labels) comes from board-renderer.js on the main
 * thread, the balls as a pose frame (pose-frame.js), the effects as
 * commands, and the time from the main thread's frame, so both paths
 * draw the same picture.
 *
 * Everything static — the background, walls, pegs, buckets and their
 * multipliers — is drawn once into a layer when the layout changes; a
 * frame is that layer, the effects (peg glows, bucket bounces with their
 * multiplier popping, floating payouts, big-win bursts) and the balls
 * with their trails.
 */

export const FLASH_MS = 520
export const GLOW_MS = 320
export const FLOAT_MS = 1300
export const BURST_MS = 1700
const MAX_PARTICLES = 240

/**
 * @typedef {object} PaintLayout what board-renderer.js laid out (structured-cloneable)
 * @property {PaintedBoard} board
 * @property {number} width device px
 * @property {number} height device px
 * @property {number} scale CSS px per board px
 * @property {number} ratio device px per CSS px
 * @property {number} bucketBottom bucket box depth below the bucket line (units)
 * @property {boolean} upright the labels stand upright
 * @property {{ text: string, px: number }[]} labels each bucket's label and its size (CSS px)
 * @property {string[]} colors each bucket's colour
 * @property {string[]} textColors each bucket's label colour
 */

/**
 * What the painter reads of a board (engine/board.js), as plain data a worker can be sent.
 * @param {import('/engine/board.js').Board} board
 * @typedef {ReturnType<typeof paintedBoard>} PaintedBoard
 */
export function paintedBoard (board) {
  const { width, height, pegRadius, ballRadius, bucketLineY, bucketLeftX, bucketWidth, dropZone } = board
  return { width, height, pegRadius, ballRadius, bucketLineY, bucketLeftX, bucketWidth, dropZone: { ...dropZone }, pegs: board.pegs.map(({ x, y }) => ({ x, y })), walls: board.walls.map((w) => w.slice()), buckets: board.multipliers.length }
}

/**
 * @typedef {object} PaintFrame
 * @property {Float64Array} poses the balls (pose-frame.js)
 * @property {number} count how many
 * @property {number} now ms, the main thread's frame time
 * @property {boolean} reducedMotion no trails
 * @property {{ trajectory: Float64Array, upto: number }} [trail] a path to draw behind the balls (replays)
 */

export class BoardPainter {
  /** @param {HTMLCanvasElement | OffscreenCanvas} canvas */
  constructor (canvas) {
    this.canvas = canvas
    this.context = canvas.getContext('2d', { alpha: false })
    /** @type {PaintLayout | null} */
    this.layout = null
    this.layer = null
    /** Ball and glow sprites at the current size (made on the first frame after a layout). */
    this._sprites = null
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
  }

  /** A new size or board: resizes the canvas and redraws the static layer. @param {PaintLayout} layout */
  setLayout (layout) {
    this.layout = layout
    this.canvas.width = layout.width
    this.canvas.height = layout.height
    this.layer ??= makeCanvas(layout.width, layout.height)
    this.layer.width = layout.width
    this.layer.height = layout.height
    this._sprites = null
    this._drawStatic()
  }

  /** An effect is still playing (as of the last frame drawn): its next frame differs. */
  get animating () {
    return this.flashes.length + this.glows.length + this.floaters.length + this.particles.length + this.bursts.length > 0
  }

  clearEffects () {
    this.flashes.length = 0
    this.glows.length = 0
    this.floaters.length = 0
    this.particles.length = 0
    this.bursts.length = 0
  }

  /**
   * An effect started (board-renderer.js's commands): ['flash', bucket, mine, now],
   * ['glow', peg, mine, now], ['float', bucket, text, now, big], ['celebrate', bucket, now].
   * @param {any[]} command
   */
  apply (command) {
    const board = this.layout?.board
    if (!board) return
    switch (command[0]) {
      case 'flash': this.flashes.push({ bucket: command[1], mine: command[2], start: command[3] }); break
      case 'glow': this._glow(command[1], command[2], command[3]); break
      case 'float': {
        const [, bucket, text, now, big] = command
        const x = board.bucketLeftX + (bucket + 0.5) * board.bucketWidth
        this.floaters.push({ text, x, y: board.bucketLineY - 10 * unitOf(board), start: now, big, color: this.layout.colors[bucket] ?? '#fff' })
        break
      }
      case 'celebrate': this._celebrate(command[1], command[2]); break
    }
  }

  _glow (peg, mine, now) {
    const glow = this.glows.find((g) => g.peg === peg)
    if (glow) {
      glow.start = now
      glow.mine = glow.mine || mine
    } else {
      this.glows.push({ peg, mine, start: now })
    }
  }

  /** A big win: sparks burst from the bucket and the board glows in its colour. */
  _celebrate (bucket, now) {
    const board = this.layout.board
    const u = unitOf(board)
    const x = board.bucketLeftX + (bucket + 0.5) * board.bucketWidth
    const y = board.bucketLineY
    const palette = ['#ffd84d', '#ff5a8a', '#7cf2c9', '#ffffff', this.layout.colors[bucket] ?? '#ffc400']
    for (let i = 0; i < 70 && this.particles.length < MAX_PARTICLES; i++) {
      const angle = -Math.PI / 2 + (Math.random() - 0.5) * Math.PI * 0.9
      const speed = (60 + Math.random() * 140) * u
      this.particles.push({ x, y, vx: Math.cos(angle) * speed, vy: Math.sin(angle) * speed, color: palette[i % palette.length], start: now, size: (2 + Math.random() * 3) * u })
    }
    this.bursts.push({ bucket, start: now })
  }

  /**
   * One frame: the static layer, then the effects and the balls. Balls and
   * peg glows are sprites drawn once per size (_makeSprites), not a
   * radial gradient and an arc per ball per frame: in software rendering
   * (no GPU) a gradient fill is what costs. (Restoring only the parts the
   * last frame drew on, from the layer, measured slower than one copy of
   * the whole layer: a copy per ball costs more than the pixels saved.)
   * @param {PaintFrame} frame
   * @returns {{ trails: number, floaterClearance: number | null } | null} the trails drawn, and the least
   *   room (CSS px) between a floating payout and the bucket boxes below it (null: none floating);
   *   null if nothing was drawn (no layout yet)
   */
  draw ({ poses, count, now, reducedMotion, trail }) {
    const ctx = this.context
    const layout = this.layout
    if (!layout || this.canvas.width === 0) return null
    const stats = { trails: 0, floaterClearance: null }
    const board = layout.board
    const s = layout.scale * layout.ratio
    const u = unitOf(board)
    this._sprites ??= this._makeSprites()
    ctx.setTransform(1, 0, 0, 1, 0, 0)
    ctx.drawImage(this.layer, 0, 0)
    ctx.setTransform(s, 0, 0, s, 0, 0)

    this._drawBursts(ctx, now, u)
    this._drawGlows(ctx, now, u, s)
    this._drawFlashes(ctx, now, u)

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
    if (!reducedMotion) {
      ctx.lineCap = 'round'
      stats.trails += this._drawTrails(ctx, poses, count, 0, 'rgba(150, 170, 230, 0.18)', r * 0.8)
      stats.trails += this._drawTrails(ctx, poses, count, 1, 'rgba(255, 110, 150, 0.30)', r * 1.1)
    }
    const sprites = this._sprites
    ctx.strokeStyle = 'rgba(30, 20, 60, 0.55)'
    ctx.lineWidth = 1.4 * u
    for (let o = 0; o < count * STRIDE; o += STRIDE) {
      const x = poses[o]
      const y = poses[o + 1]
      const angle = poses[o + 2]
      ctx.globalAlpha = Math.max(0, Math.min(1, poses[o + 3]))
      // Own balls: a halo, and warm colours; the others' cool.
      const sprite = poses[o + 4] === 1 ? sprites.mine : sprites.other
      const half = sprite.width / 2
      ctx.setTransform(1, 0, 0, 1, 0, 0)
      ctx.drawImage(sprite, Math.round(x * s - half), Math.round(y * s - half))
      ctx.setTransform(s, 0, 0, s, 0, 0)
      // A mark on the ball shows its spin.
      ctx.beginPath()
      ctx.moveTo(x, y)
      ctx.lineTo(x + Math.cos(angle) * r * 0.85, y + Math.sin(angle) * r * 0.85)
      ctx.stroke()
    }
    ctx.globalAlpha = 1

    this._drawParticles(ctx, now)
    stats.floaterClearance = this._drawFloaters(ctx, now, u)
    ctx.globalAlpha = 1
    return stats
  }

  /**
   * The trails of the balls that are the player's own (`mine` 1) or not,
   * as one path stroked once: a stroke per trail cost more than everything
   * else in a frame under software rendering; where two trails of a kind
   * cross, they no longer darken each other. Returns how many were drawn.
   */
  _drawTrails (ctx, poses, count, mine, color, width) {
    let drawn = 0
    ctx.beginPath()
    for (let o = 0; o < count * STRIDE; o += STRIDE) {
      const points = poses[o + 5]
      if (poses[o + 4] !== mine || points === 0) continue
      ctx.moveTo(poses[o], poses[o + 1])
      for (let p = 0; p < points; p++) ctx.lineTo(poses[o + 6 + 2 * p], poses[o + 7 + 2 * p])
      drawn++
    }
    if (drawn === 0) return 0
    ctx.strokeStyle = color
    ctx.lineWidth = width
    ctx.stroke()
    return drawn
  }

  /**
   * The balls and the peg glows drawn once at this size (device px): an
   * own ball with its halo, another player's, and a glow of each kind at
   * its largest (drawn smaller as it grows, fainter as it fades).
   */
  _makeSprites () {
    const { board, scale, ratio } = this.layout
    const s = scale * ratio
    const r = board.ballRadius
    const sprite = (reach, paint) => {
      const size = Math.ceil(2 * reach * s) + 4
      const canvas = makeCanvas(size, size)
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
    const board = this.layout.board
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

  _drawFlashes (ctx, now, u) {
    const { board, bucketBottom, colors } = this.layout
    this.flashes = this.flashes.filter((f) => now - f.start < FLASH_MS)
    const height = (BUCKET_TOP + bucketBottom) * u
    for (const f of this.flashes) {
      if (f.bucket >= board.buckets) continue
      const t = (now - f.start) / FLASH_MS
      const x = board.bucketLeftX + f.bucket * board.bucketWidth
      // The bucket dips and springs back; its label pops.
      const dip = 4 * Math.sin(Math.min(1, t * 1.6) * Math.PI) * (1 - t) * u
      const top = board.bucketLineY - BUCKET_TOP * u + dip
      ctx.globalAlpha = 1
      ctx.fillStyle = '#0b1024'
      ctx.fillRect(x + 1 * u, board.bucketLineY - BUCKET_TOP * u, board.bucketWidth - 2 * u, height + 5 * u)
      ctx.fillStyle = colors[f.bucket]
      roundRect(ctx, x + 2 * u, top, board.bucketWidth - 4 * u, height, 4 * u)
      ctx.fill()
      ctx.globalAlpha = (1 - t) * 0.7
      ctx.fillStyle = f.mine ? '#ffffff' : '#cfd8ff'
      roundRect(ctx, x + 2 * u, top, board.bucketWidth - 4 * u, height, 4 * u)
      ctx.fill()
      ctx.globalAlpha = 1
      const pop = 1 + 0.45 * Math.sin(Math.min(1, t * 2) * Math.PI)
      this._label(ctx, f.bucket, x + board.bucketWidth / 2, top + height / 2 + 0.5 * u, pop)
    }
    ctx.globalAlpha = 1
  }

  /** The floating payouts; returns the least room between one and the bucket boxes (CSS px), or null. */
  _drawFloaters (ctx, now, u) {
    const { board, scale } = this.layout
    let least = null
    this.floaters = this.floaters.filter((f) => now - f.start < FLOAT_MS)
    for (const f of this.floaters) {
      const t = (now - f.start) / FLOAT_MS
      const base = f.big ? 22 : 14
      const px = base * (1 + 0.15 * Math.sin(Math.min(1, t * 3) * Math.PI))
      ctx.font = `800 ${px / scale}px system-ui, sans-serif`
      ctx.textAlign = 'center'
      ctx.textBaseline = 'middle'
      const metrics = ctx.measureText(f.text)
      // Start with the text's lowest point (at its largest) clear of the bucket boxes, so it never covers their labels.
      const bucketTop = board.bucketLineY - BUCKET_TOP * u
      const stroke = 1.5 / scale
      const start = Math.min(f.y, bucketTop - 2 * u - metrics.actualBoundingBoxDescent * 1.15 * base / px - stroke)
      const y = start - (f.big ? 40 : 24) * u * easeOut(t)
      const clearance = (bucketTop - (y + metrics.actualBoundingBoxDescent + stroke)) * scale
      least = Math.min(least ?? Infinity, clearance)
      // Keep the text on the board.
      const half = metrics.width / 2
      const x = Math.max(half + 2 * u, Math.min(board.width - half - 2 * u, f.x))
      ctx.globalAlpha = t < 0.7 ? 1 : (1 - t) / 0.3
      ctx.lineWidth = 3 / scale
      ctx.strokeStyle = 'rgba(10, 8, 30, 0.85)'
      ctx.strokeText(f.text, x, y)
      ctx.fillStyle = f.big ? '#ffd84d' : '#7cf29a'
      ctx.fillText(f.text, x, y)
    }
    ctx.globalAlpha = 1
    return least
  }

  _drawBursts (ctx, now, u) {
    const board = this.layout.board
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
    const board = this.layout.board
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

  /** Bucket `i`'s label (as laid out) centred at (x, y), flat or upright, `pop` times its size. */
  _label (ctx, i, x, y, pop = 1) {
    const { labels, textColors, upright, scale } = this.layout
    const label = labels[i]
    if (!label) return
    ctx.save()
    ctx.fillStyle = textColors[i] ?? '#000'
    ctx.textAlign = 'center'
    ctx.textBaseline = 'middle'
    ctx.translate(x, y)
    if (upright) ctx.rotate(-Math.PI / 2)
    ctx.font = labelFont(label.px * pop / scale)
    ctx.fillText(label.text, 0, 0)
    ctx.restore()
  }

  _drawStatic () {
    const { board, scale, ratio, bucketBottom, colors } = this.layout
    const ctx = this.layer.getContext('2d', { alpha: false })
    const s = scale * ratio
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
    const height = (BUCKET_TOP + bucketBottom) * u
    for (let i = 0; i < board.buckets; i++) {
      const x = board.bucketLeftX + i * board.bucketWidth
      ctx.fillStyle = colors[i]
      roundRect(ctx, x + 2 * u, top, board.bucketWidth - 4 * u, height, 4 * u)
      ctx.fill()
      this._label(ctx, i, x + board.bucketWidth / 2, top + height / 2 + 0.5 * u)
    }
  }
}

function easeOut (t) {
  return 1 - (1 - t) * (1 - t)
}

function roundRect (ctx, x, y, width, height, radius) {
  ctx.beginPath()
  ctx.roundRect(x, y, width, height, radius)
}
