/**
 * A one-line progress bar for a terminal stream (redrawn with \r at most
 * every 100 ms); on a non-TTY it prints a line every 10%.
 */
export class ProgressBar {
  /** @param {number} total @param {NodeJS.WriteStream} stream @param {string} label */
  constructor (total, stream, label) {
    this.total = total
    this.stream = stream
    this.label = label
    this.started = performance.now()
    this._lastDraw = 0
    this._lastDecile = -1
  }

  /** @param {number} done */
  update (done) {
    const now = performance.now()
    const fraction = this.total > 0 ? Math.min(1, done / this.total) : 1
    if (this.stream.isTTY) {
      if (now - this._lastDraw < 100 && done < this.total) return
      this._lastDraw = now
      const width = 30
      const filled = Math.round(fraction * width)
      const rate = done / Math.max(1e-9, (now - this.started) / 1000)
      this.stream.write(`\r${this.label} [${'#'.repeat(filled)}${'.'.repeat(width - filled)}] ${(fraction * 100).toFixed(1)}% ${done}/${this.total} ${Math.round(rate)}/s`)
    } else {
      const decile = Math.floor(fraction * 10)
      if (decile === this._lastDecile) return
      this._lastDecile = decile
      this.stream.write(`${this.label} ${decile * 10}% (${done}/${this.total})\n`)
    }
  }

  finish () {
    if (this.stream.isTTY) this.stream.write('\n')
  }
}
