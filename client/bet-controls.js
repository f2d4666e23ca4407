import { byId, el, formatAmount } from './dom.js'
import { parseRoomId, roomIdOf, ROWS, RISKS } from '/protocol/room-id.js'
import { clampBet, STOP_RULE } from './auto-bet.js'

const BET_KEY = 'plinko.bet'

/**
 * The controls under the board: rows and risk (the room), the bet with ½
 * and 2×, Drop (the button, a tap on the board, Space), the auto-bet's
 * buttons, the session reset and mute; and the keys: Space drops, S halves,
 * D doubles, A starts or stops the auto-bet, M mutes.
 */
export class BetControls {
  /** @param {import('./player.js').PlayerPage} page */
  constructor (page) {
    this.page = page
    /** the last `ref` number sent with a drop (own and auto-bet drops count alike) */
    this.refs = 0
  }

  /** A new drop ref: `drop-1`, `auto-2`… @param {string} prefix */
  nextRef (prefix) {
    return `${prefix}-${++this.refs}`
  }

  setUp () {
    const { auto, results } = this.page
    const { rows, risk } = parseRoomId(this.page.connection.roomId)
    const rowsSelect = byId('rows')
    const riskSelect = byId('risk')
    for (const r of ROWS) rowsSelect.append(el('option', { value: String(r), text: String(r), selected: r === rows }))
    for (const k of RISKS) riskSelect.append(el('option', { value: k, text: k, selected: k === risk }))
    const onRoom = () => this.changeBoard(Number(rowsSelect.value), riskSelect.value)
    rowsSelect.addEventListener('change', onRoom)
    riskSelect.addEventListener('change', onRoom)

    const bet = byId('bet')
    bet.value = localStorage.getItem(BET_KEY) ?? '10'
    for (const button of document.querySelectorAll('[data-bet]')) {
      button.addEventListener('click', () => this.changeBet(button.dataset.bet))
    }
    byId('drop').addEventListener('click', () => this.drop())
    byId('board').addEventListener('click', () => this.drop())
    byId('auto-rule').textContent = STOP_RULE
    byId('auto').addEventListener('click', () => auto.toggle())
    byId('auto-resume').addEventListener('click', () => auto.resume())
    byId('session-reset').addEventListener('click', () => results.resetSession())
    const toggleMute = this.setUpMute()
    this.setUpKeys(toggleMute)
  }

  /** The mute button; returns what toggles it. */
  setUpMute () {
    const { sound } = this.page
    const mute = byId('mute')
    const showMute = () => {
      mute.setAttribute('aria-pressed', String(sound.muted))
      mute.setAttribute('aria-label', sound.muted ? 'Unmute sound' : 'Mute sound')
      mute.title = sound.muted ? 'Sound off (M)' : 'Sound on (M)'
    }
    const toggleMute = () => { sound.setMuted(!sound.muted); showMute() }
    mute.addEventListener('click', toggleMute)
    showMute()
    return toggleMute
  }

  /**
   * Keys: none while typing text, or while a recalled drop is open. Space
   * belongs to a focused control (a button presses, a summary opens): it
   * drops only when nothing interactive has focus, or the Drop button has it.
   */
  setUpKeys (toggleMute) {
    const { recall, auto } = this.page
    const keys = {
      Space: () => this.drop(),
      KeyS: () => this.changeBet('half'),
      KeyD: () => this.changeBet('double'),
      KeyA: () => auto.toggle(),
      KeyM: toggleMute
    }
    document.addEventListener('keydown', (event) => {
      const action = keys[event.code]
      if (!action || event.ctrlKey || event.metaKey || event.altKey || isTyping(event.target) || recall.isOpen) return
      if (event.code === 'Space' && !spaceDrops(event.target)) return
      event.preventDefault()
      if (!event.repeat) action()
    })
    // Space on the focused Drop button would click it as well: the keydown above already dropped.
    document.addEventListener('keyup', (event) => {
      if (event.code === 'Space' && event.target === byId('drop') && !recall.isOpen) event.preventDefault()
    })
  }

  /**
   * A board change from the controls: refused (the selects put back) while
   * the player's own balls are still falling or an auto-bet runs, so no
   * ball of theirs ever vanishes from the board.
   */
  changeBoard (rows, risk) {
    const { connection, auto, notices } = this.page
    const inFlight = connection.view ? connection.view.ownInFlight : 0
    const current = parseRoomId(connection.roomId)
    const autoRunning = auto.running
    if (inFlight > 0 || autoRunning) {
      byId('rows').value = String(current.rows)
      byId('risk').value = current.risk
      notices.say(autoRunning
        ? 'Stop the auto-bet before changing the board.'
        : `Wait for your ${inFlight} ball${inFlight === 1 ? '' : 's'} in flight to land before changing the board.`, 'error')
      return false
    }
    connection.join(roomIdOf(rows, risk))
    return true
  }

  /** @param {string} [ref] @param {number} [betOverride] the auto-bet's bet */
  drop (ref = this.nextRef('drop'), betOverride) {
    const { account, connection, notices } = this.page
    const bet = betOverride ?? Number(byId('bet').value)
    if (!Number.isSafeInteger(bet) || bet < account.minBet || bet > account.maxBet) {
      notices.say(`The bet must be a whole number from ${account.minBet} to ${formatAmount(account.maxBet)}.`, 'error')
      return false
    }
    if (account.balance !== null && bet > account.balance) {
      notices.say('Not enough balance for this bet.', 'error')
      return false
    }
    if (!connection.joinedRoom || !connection.socket.send({ type: 'drop', bet, ref })) {
      notices.say('Not connected: the drop was not sent.', 'error')
      return false
    }
    if (betOverride === undefined) localStorage.setItem(BET_KEY, String(bet))
    return true
  }

  /** ½ and 2×: within MIN_BET, MAX_BET and the balance. @param {'half' | 'double'} how */
  changeBet (how) {
    const { account } = this.page
    const input = byId('bet')
    const value = Number(input.value) || account.minBet
    const next = how === 'half' ? Math.floor(value / 2) : value * 2
    const clamped = clampBet(next, { minBet: account.minBet, maxBet: account.maxBet }, account.balance)
    input.value = String(clamped ?? account.minBet)
    if (how === 'double' && clamped !== null && clamped < next) this.page.notices.say(`The bet is capped at ${formatAmount(clamped)} (${clamped === account.maxBet ? 'the table limit' : 'your balance'}).`)
  }
}

/** Space drops from the Drop button, or when what has focus is nothing a user operates. */
function spaceDrops (target) {
  if (target === byId('drop')) return true
  if (!(target instanceof Element)) return true
  return target.closest('button, a[href], input, select, textarea, summary, [tabindex], [contenteditable=""], [contenteditable="true"], [role="button"]') === null
}

/** Typing text (where Space and letters are the user's): text fields, text areas, selects, editable content. */
function isTyping (target) {
  if (!(target instanceof HTMLElement)) return false
  if (target.isContentEditable || target.tagName === 'TEXTAREA' || target.tagName === 'SELECT') return true
  return target.tagName === 'INPUT' && !['number', 'range', 'checkbox', 'radio', 'button', 'submit'].includes(/** @type {HTMLInputElement} */ (target).type)
}
