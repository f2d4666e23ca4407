import { el, formatMultiplier, exactMultiplier } from './dom.js'

/** Results shown. */
export const RECENT_RESULTS = 16

/**
 * The player's last results as chips above the board, newest first, each
 * coloured like the bucket it landed in. The strip's height is reserved
 * (CSS) so the board never moves when the first result appears.
 */
export class ResultsStrip {
  /** @param {HTMLOListElement} list */
  constructor (list) {
    this.list = list
    /** @type {{ dropId: number, multiplier: number, bucket: number, color: string }[]} newest first */
    this.entries = []
  }

  /** @param {{ dropId: number, multiplier: number, bucket: number, color: string, textColor?: string }} result */
  add (result) {
    if (this.entries.some((e) => e.dropId === result.dropId)) return
    this.entries.unshift(result)
    this.list.querySelector('.placeholder')?.remove()
    const chip = el('li', { class: 'chip fresh', title: `drop #${result.dropId}: bucket ${result.bucket}, ${exactMultiplier(result.multiplier)}`, dataset: { dropId: String(result.dropId) }, text: formatMultiplier(result.multiplier) })
    chip.style.background = result.color
    if (result.textColor) chip.style.color = result.textColor
    this.list.prepend(chip)
    while (this.entries.length > RECENT_RESULTS) {
      this.entries.pop()
      this.list.lastElementChild?.remove()
    }
  }
}
