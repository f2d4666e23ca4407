import { byId, el } from './dom.js'

/**
 * What the page tells the player: one status line (replaced by the next
 * message) and the warnings box, where each warning stays (and is kept in
 * `warnings` for tests).
 */
export class PageNotices {
  constructor () {
    /** @type {string[]} every warning shown, oldest first */
    this.warnings = []
  }

  /** The status line under the controls. @param {string} text @param {string} [kind] 'info' or 'error' */
  say (text, kind = 'info') {
    const line = byId('message')
    line.textContent = text
    line.dataset.kind = kind
  }

  /** A lasting warning (a drop that did not verify, an engine the page lacks). @param {string} text */
  warn (text) {
    this.warnings.push(text)
    const box = byId('alert')
    box.hidden = false
    box.append(el('p', { text: `⚠ ${text}` }))
  }
}
