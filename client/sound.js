/**
 * The page's sounds, synthesized with the Web Audio API (no downloaded
 * assets): a short peg tick whose pitch rises row by row, and a landing
 * chime that grows with the multiplier (a rising arpeggio for big wins).
 * Browsers allow audio only after a user gesture, so nothing is created
 * before the first click, tap or key press; muting is remembered in
 * localStorage.
 */

export const MUTE_KEY = 'plinko.muted'
/** At most this many peg ticks per second, whatever the number of balls. */
const MAX_TICKS_PER_SECOND = 40

export class Sound {
  constructor (storage = globalThis.localStorage) {
    this.storage = storage
    this.muted = storage.getItem(MUTE_KEY) === '1'
    /** @type {AudioContext | null} */
    this.context = null
    this.master = null
    /** A user gesture has happened: audio may play. */
    this.unlocked = false
    /** Sounds started so far (for tests and the curious). */
    this.played = { ticks: 0, landings: 0 }
    this._tickTimes = []
    const unlock = () => {
      this.unlocked = true
      if (!this.muted) this._ensure()
      for (const type of ['pointerdown', 'keydown', 'touchend']) removeEventListener(type, unlock, true)
    }
    for (const type of ['pointerdown', 'keydown', 'touchend']) addEventListener(type, unlock, { capture: true })
  }

  /** Running and audible. */
  get active () {
    return this.unlocked && !this.muted && this.context !== null
  }

  /** @param {boolean} muted */
  setMuted (muted) {
    this.muted = muted
    this.storage.setItem(MUTE_KEY, muted ? '1' : '0')
    if (!muted && this.unlocked) this._ensure()
    if (this.context) {
      if (muted) this.context.suspend().catch(() => {})
      else this.context.resume().catch(() => {})
    }
  }

  _ensure () {
    if (this.context) {
      if (this.context.state === 'suspended') this.context.resume().catch(() => {})
      return
    }
    const AudioContextClass = globalThis.AudioContext ?? globalThis.webkitAudioContext
    if (!AudioContextClass) return
    this.context = new AudioContextClass()
    this.master = this.context.createGain()
    this.master.gain.value = 0.35
    this.master.connect(this.context.destination)
  }

  /**
   * A peg contact.
   * @param {number} row 0 = top @param {number} rows rows on the board @param {boolean} mine others' balls tick softer
   */
  pegTick (row, rows, mine) {
    if (!this.active) return
    const now = performance.now()
    const times = this._tickTimes
    while (times.length > 0 && now - times[0] > 1000) times.shift()
    if (times.length >= MAX_TICKS_PER_SECOND) return
    times.push(now)
    const ctx = this.context
    const t = ctx.currentTime
    const osc = ctx.createOscillator()
    const gain = ctx.createGain()
    osc.type = 'triangle'
    // Two octaves from the top row to the bottom one.
    osc.frequency.value = 520 * 2 ** (2 * row / Math.max(1, rows - 1))
    gain.gain.setValueAtTime(mine ? 0.16 : 0.05, t)
    gain.gain.exponentialRampToValueAtTime(0.0001, t + 0.06)
    osc.connect(gain).connect(this.master)
    osc.start(t)
    osc.stop(t + 0.07)
    this.played.ticks++
  }

  /** A ball landing in a bucket of `multiplier`. @param {number} multiplier @param {boolean} mine */
  landing (multiplier, mine) {
    if (!this.active || !mine) return
    const ctx = this.context
    const t = ctx.currentTime
    // Louder, higher and longer the bigger the win; a falling blip for a loss.
    const win = multiplier >= 1
    const level = Math.min(1, Math.log2(1 + multiplier) / Math.log2(1001))
    const notes = multiplier >= 10 ? [0, 4, 7, 12, 16] : multiplier >= 2 ? [0, 4, 7] : [0]
    const base = win ? 330 * (1 + level) : 220
    notes.forEach((semitones, i) => {
      const start = t + i * 0.07
      const osc = ctx.createOscillator()
      const gain = ctx.createGain()
      osc.type = win ? 'sine' : 'square'
      osc.frequency.setValueAtTime(base * 2 ** (semitones / 12), start)
      if (!win) osc.frequency.exponentialRampToValueAtTime(base * 0.6, start + 0.12)
      const peak = win ? 0.12 + 0.25 * level : 0.04
      const length = win ? 0.18 + 0.5 * level : 0.12
      gain.gain.setValueAtTime(0.0001, start)
      gain.gain.exponentialRampToValueAtTime(peak, start + 0.01)
      gain.gain.exponentialRampToValueAtTime(0.0001, start + length)
      osc.connect(gain).connect(this.master)
      osc.start(start)
      osc.stop(start + length + 0.02)
    })
    this.played.landings++
  }
}
