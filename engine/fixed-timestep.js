/**
 * The fixed-timestep accumulator ("Fix your timestep!"): real time goes in,
 * a whole number of fixed steps comes out, and the remainder becomes the
 * interpolation alpha. Steps per call are capped, and time beyond the cap is
 * dropped, so a stalled frame cannot make the next one even slower.
 */
export class FixedTimestep {
  /**
   * @param {object} options
   * @param {number} options.timestep seconds per step
   * @param {number} options.maxSteps most steps one advance() may ask for
   */
  constructor ({ timestep, maxSteps }) {
    if (!(timestep > 0)) throw new RangeError('timestep must be > 0')
    if (!(Number.isInteger(maxSteps) && maxSteps >= 1)) throw new RangeError('maxSteps must be an integer >= 1')
    this.timestep = timestep
    this.maxSteps = maxSteps
    this.accumulator = 0
    this.droppedTime = 0
  }

  /**
   * @param {number} frameTime elapsed seconds (negative or non-finite counts as 0)
   * @returns {number} steps to run now
   */
  advance (frameTime) {
    if (frameTime > 0 && frameTime < Infinity) this.accumulator += frameTime
    let steps = 0
    while (this.accumulator >= this.timestep && steps < this.maxSteps) {
      this.accumulator -= this.timestep
      steps++
    }
    if (this.accumulator >= this.timestep) {
      // Spiral guard: keep the fractional part only.
      const excess = this.accumulator - this.accumulator % this.timestep
      this.droppedTime += excess
      this.accumulator -= excess
    }
    return steps
  }

  /** Interpolation factor between the previous and current step, in [0, 1). */
  get alpha () {
    return this.accumulator / this.timestep
  }
}
