import { byId, el, formatAmount, formatSigned } from './dom.js'
import { AutoBet } from './auto-bet.js'

const AUTO_DROP_EVERY_MS = 250

/**
 * The auto-bet's form, button and status box around one run
 * (client/auto-bet.js holds its rules): a drop every AUTO_DROP_EVERY_MS
 * while it runs, its results fed back as they settle, stopped by its rules,
 * a refusal or a lost connection (and resumable after that).
 */
export class AutoBetControls {
  /** @param {import('./player.js').PlayerPage} page */
  constructor (page) {
    this.page = page
    /** @type {AutoBet | null} the running (or last) run */
    this.run = null
    this.timer = null
  }

  /** Sending drops right now. */
  get running () {
    return Boolean(this.run?.running && this.timer !== null)
  }

  toggle () {
    if (this.running) this.stop('stopped')
    else this.start()
  }

  /** Reads the auto-bet form; undefined (and a message) when something is off. */
  rules () {
    const { account, notices } = this.page
    const count = Number(byId('auto-count').value)
    const baseBet = Number(byId('bet').value)
    const optional = (id) => {
      const text = byId(id).value.trim()
      return text === '' || Number(text) === 0 ? null : Number(text)
    }
    const stopProfit = optional('auto-stop-profit')
    const stopLoss = optional('auto-stop-loss')
    const rule = (modeId, percentId) => ({ mode: byId(modeId).value === 'increase' ? 'increase' : 'reset', percent: Number(byId(percentId).value) || 0 })
    const guard = /** @type {HTMLInputElement} */ (byId('auto-guard')).checked
    const rules = { count, baseBet, stopProfit, stopLoss, guard, onWin: rule('auto-on-win', 'auto-win-percent'), onLoss: rule('auto-on-loss', 'auto-loss-percent') }
    if (!Number.isSafeInteger(count) || count < 1) return notices.say('Auto-bet needs a number of bets (1 or more).', 'error')
    if (!Number.isSafeInteger(baseBet) || baseBet < account.minBet || baseBet > account.maxBet) return notices.say(`The bet must be a whole number from ${account.minBet} to ${formatAmount(account.maxBet)}.`, 'error')
    for (const limit of [stopProfit, stopLoss]) if (limit !== null && !(limit > 0)) return notices.say('Stop on profit and stop on loss are amounts above 0 (or empty: off).', 'error')
    for (const r of [rules.onWin, rules.onLoss]) if (!(r.percent >= 0 && r.percent <= 1000)) return notices.say('Increase by 0 to 1000 %.', 'error')
    return rules
  }

  start () {
    const rules = this.rules()
    if (!rules) return
    if (!this.page.connection.joinedRoom) return this.page.notices.say('Not connected: auto-bet did not start.', 'error')
    this.run = new AutoBet(rules, { minBet: this.page.account.minBet, maxBet: this.page.account.maxBet })
    this.send()
  }

  /** Continues a run stopped by a lost connection, with the bets it had left. */
  resume () {
    const run = this.run
    if (!run || run.stopReason !== 'disconnected' || run.remaining <= 0) return
    if (!this.page.connection.joinedRoom) return this.page.notices.say('Still not connected: the auto-bet can resume once the page is back in its room.', 'error')
    run.resume()
    this.page.notices.say(`Auto-bet resumed: ${run.remaining} bets left.`)
    this.send()
  }

  /** Sends the run's drops, one now and one every AUTO_DROP_EVERY_MS. */
  send () {
    const run = this.run
    const { bets, connection, account } = this.page
    const tick = () => {
      if (!run.running) return this.stop(run.stopReason)
      const bet = run.nextBet(account.balance)
      if (bet === null) return this.stop('balance')
      const guard = run.guardBet(bet)
      if (guard === 'stop') return this.stop('guard')
      if (guard === 'wait') return this.showStatus()
      const ref = bets.nextRef('auto')
      if (!bets.drop(ref, bet)) return this.stop(connection.joinedRoom ? 'refused' : 'disconnected')
      run.markSent(ref, bet)
      this.renderButton()
      if (!run.running) this.stop(run.stopReason)
      else this.showStatus()
    }
    clearInterval(this.timer)
    this.timer = setInterval(tick, AUTO_DROP_EVERY_MS)
    tick()
  }

  /** Own `dropped`: the drop id of one of the run's refs. */
  dropped (message) {
    if (typeof message.ref === 'string' && this.run?.refs.has(message.ref)) this.run.dropIds.add(message.dropId)
  }

  /** A settled drop of the run: its bet for the next drop, and its stop rules. */
  result (settled) {
    const run = this.run
    if (!run || !run.dropIds.has(settled.dropId)) return
    const stopped = run.result({ bet: settled.bet, payout: settled.payout, dropId: settled.dropId })
    if (stopped) this.stop(stopped)
    else this.showStatus()
  }

  /** An `error` for one of the run's drops: that ball again later, or a stop when retrying cannot help. */
  refused (message) {
    const run = this.run
    if (typeof message.ref !== 'string' || !run || !run.refs.has(message.ref)) return
    if (run.running && (message.code === 'E_RATE_LIMITED' || message.code === 'E_ROOM_FULL' || message.code === 'E_SEED_ROTATING')) {
      run.retry(message.ref)
      this.renderButton()
    } else {
      this.stop(message.code === 'E_INSUFFICIENT_FUNDS' ? 'balance' : 'refused', message.code)
    }
  }

  /** The connection is not open (any more): a running run stops, a stopped one shows whether it can resume. */
  connectionChanged (open) {
    if (!open) this.disconnected()
    if (this.run) this.showStatus()
  }

  /** The socket closed: a running run stops (resumable). */
  disconnected () {
    if (this.run?.running) this.stop('disconnected')
  }

  /** Back in a room: a run the lost connection stopped can resume now. */
  rejoined () {
    if (this.run && this.run.stopReason === 'disconnected') this.showStatus()
  }

  /** @param {AutoBet['stopReason']} reason @param {string} [detail] */
  stop (reason = 'stopped', detail) {
    clearInterval(this.timer)
    this.timer = null
    const run = this.run
    if (run) {
      run.stop(reason)
      if (detail) run.detail = detail
    }
    this.renderButton()
    this.showStatus()
  }

  showStatus () {
    const run = this.run
    const box = byId('auto-status')
    if (!run) { box.hidden = true; return }
    box.hidden = false
    box.dataset.state = run.running ? 'running' : run.finished ? 'finished' : run.stopReason
    byId('auto-status-text').textContent = autoStatusText(run)
    if (run.finished && !run.announced) {
      run.announced = true
      this.page.announcer.say(autoStatusText(run))
    }
    const joined = this.page.connection.joinedRoom
    const resumable = run.stopReason === 'disconnected' && run.remaining > 0
    const resume = byId('auto-resume')
    resume.hidden = !resumable
    resume.disabled = !joined
    resume.textContent = joined ? `Resume (${run.remaining} left)` : `Resume (${run.remaining} left) once reconnected`
  }

  renderButton () {
    const button = byId('auto')
    const running = this.running
    button.replaceChildren(running ? `Stop (${this.run.remaining})` : 'Auto', ' ', el('kbd', { class: 'key-hint', text: 'A' }))
    button.classList.toggle('running', running)
  }

  /** What tests read: the run as it stands. */
  get probe () {
    const run = this.run
    return run ? { running: run.running && this.timer !== null, stopReason: run.stopReason, sent: run.sent, settled: run.settled, inFlight: run.inFlight, finished: run.finished, stoppedAt: run.stoppedAt && { ...run.stoppedAt }, remaining: run.remaining, profit: run.profit, bet: run.bet, log: run.log.slice(), dropIds: [...run.dropIds] } : null
  }
}

/** Why a run stopped sending, with where it stood then (`run.stoppedAt`). */
const AUTO_STOPS = {
  done: (run, at) => `Auto-bet sent all ${at.sent} bets.`,
  profit: (run, at) => `Auto-bet stopped sending at ${formatSigned(at.profit)}: the stop on profit of ${formatAmount(run.rules.stopProfit)} was reached.`,
  loss: (run, at) => `Auto-bet stopped sending at ${formatSigned(at.profit)}: the stop on loss of ${formatAmount(run.rules.stopLoss)} was reached.`,
  guard: (run, at) => `Auto-bet stopped sending at ${formatSigned(at.profit)}: the next bet of ${formatAmount(run.bet)} could take the loss past the stop on loss of ${formatAmount(run.rules.stopLoss)}.`,
  balance: (run, at) => `Auto-bet stopped after ${at.sent} bets: the balance does not cover the bet.`,
  disconnected: (run, at) => `Auto-bet stopped: the connection was lost after ${at.sent} of ${run.rules.count} bets.`,
  refused: (run, at) => `Auto-bet stopped after ${at.sent} bets: a drop was refused${run.detail ? ` (${run.detail})` : ''}.`,
  stopped: (run, at) => `Auto-bet stopped after ${at.sent} of ${run.rules.count} bets.`
}

/** The run's status: while sending, its progress; once stopped, why and where, then one final result once its last ball has landed. */
function autoStatusText (run) {
  if (run.running) return `Auto-bet: ${run.sent} of ${run.rules.count} sent, next bet ${formatAmount(run.bet)}, profit ${formatSigned(run.profit)}${run.inFlight > 0 ? ` (${run.inFlight} falling)` : ''}.`
  const why = AUTO_STOPS[run.stopReason](run, run.stoppedAt ?? { profit: run.profit, sent: run.sent, settled: run.settled })
  if (!run.finished) return `${why} ${run.inFlight} ball${run.inFlight === 1 ? '' : 's'} still falling: the final result follows when ${run.inFlight === 1 ? 'it lands' : 'they land'}.`
  const late = run.settled - (run.stoppedAt?.settled ?? run.settled)
  return `${why} Final result: ${formatSigned(run.profit)} over ${run.settled} bet${run.settled === 1 ? '' : 's'}${late > 0 ? `, counting the ${late} ball${late === 1 ? '' : 's'} still falling when it stopped` : ''}.`
}
