/**
 * Auto-bet: the rules of one run (how many bets, when to stop, how the bet
 * changes after a win or a loss) and its running state. No DOM and no
 * timers: the page asks `nextBet()` before each drop, reports each sent
 * drop and each settled result, and stops when `stopReason` is set.
 * A win is a payout above the bet. The profit is summed in integer
 * milli-credits, so a stop on profit or loss compares exact amounts.
 *
 * The stop rule (STOP_RULE, shown on the page): a run stops sending once
 * its settled profit reaches the stop on profit, or its loss the stop on
 * loss; the balls already falling then still land and count, so the run's
 * final result is known only once they have (`finished`). With `guard`, a
 * bet is held back while it could take the loss past the stop on loss if
 * it and every ball still falling were lost, and the run stops once even
 * with nothing falling it could.
 */

/** The stop rule, in one sentence for the page. */
export const STOP_RULE = 'Auto-bet stops sending once the profit of its landed balls reaches the stop on profit or their loss the stop on loss; balls already falling then still land and count in its final result.'

import { toCredits, toMilli } from '/protocol/payout.js'

/**
 * @typedef {object} AutoBetRules
 * @property {number} count bets to place
 * @property {number} baseBet the bet the run starts with (and resets to)
 * @property {number | null} stopProfit stop once the run's profit reaches this (null: never)
 * @property {number | null} stopLoss stop once the run's loss reaches this (null: never)
 * @property {{ mode: 'reset' | 'increase', percent: number }} onWin
 * @property {{ mode: 'reset' | 'increase', percent: number }} onLoss
 * @property {boolean} [guard] never send a bet that could take the loss past stopLoss
 */

export class AutoBet {
  /** @param {AutoBetRules} rules @param {{ minBet: number, maxBet: number }} limits */
  constructor (rules, limits) {
    this.rules = rules
    this.limits = limits
    this.remaining = rules.count
    this.sent = 0
    this.settled = 0
    this.profitMilli = 0
    this.bet = rules.baseBet
    /** @type {null | 'done' | 'profit' | 'loss' | 'guard' | 'balance' | 'disconnected' | 'stopped' | 'refused'} */
    this.stopReason = null
    /** @type {{ profit: number, sent: number, settled: number } | null} where the run stood when it stopped sending */
    this.stoppedAt = null
    /** milli-credits bet by drops sent and not settled yet */
    this.outstandingMilli = 0
    /** @type {Map<string, number>} the bet of each sent drop, by ref */
    this.refBets = new Map()
    /** @type {Set<number>} drops whose result is counted */
    this.settledIds = new Set()
    /** @type {Set<string>} refs of the drops this run sent */
    this.refs = new Set()
    /** @type {Set<number>} ids of the drops this run sent (as the server announced them) */
    this.dropIds = new Set()
    /**
     * Each settled result, in order; `whileRunning`: the run was still sending (a result after it stopped, of a ball still in flight, stops nothing).
     * @type {{ bet: number, payout: number, win: boolean, betBefore: number, betAfter: number, profit: number, whileRunning: boolean }[]}
     */
    this.log = []
    /** The page has announced the run's end (its final result). */
    this.announced = false
  }

  /** Credits won minus credits wagered by this run's settled drops. */
  get profit () {
    return toCredits(this.profitMilli)
  }

  get running () {
    return this.stopReason === null
  }

  /** The run's balls sent and not settled yet. */
  get inFlight () {
    return this.sent - this.settled
  }

  /** Stopped, and every ball it sent has settled: its profit is final. */
  get finished () {
    return this.stopReason !== null && this.inFlight <= 0
  }

  /**
   * With `guard` and a stop on loss: 'wait' while `bet` could take the loss
   * past it together with the balls still falling, 'stop' when it could on
   * its own; else 'send'. @param {number} bet
   */
  guardBet (bet) {
    const { guard, stopLoss } = this.rules
    if (!guard || stopLoss === null) return 'send'
    const limit = toMilli(stopLoss)
    if (-(this.profitMilli - toMilli(bet)) > limit) return 'stop'
    if (-(this.profitMilli - this.outstandingMilli - toMilli(bet)) > limit) return 'wait'
    return 'send'
  }

  /** The bet for the next drop, clamped to the limits and `balance`; null when the balance cannot cover the minimum. @param {number | null} balance */
  nextBet (balance) {
    return clampBet(this.bet, this.limits, balance)
  }

  /** A drop of this run went out. @param {string} ref @param {number} [bet] */
  markSent (ref, bet = this.bet) {
    this.refs.add(ref)
    this.refBets.set(ref, bet)
    this.outstandingMilli += toMilli(bet)
    this.sent++
    this.remaining--
    if (this.remaining <= 0) this.stop('done')
  }

  /** A sent drop was refused and may be retried (rate limit, full room). @param {string} [ref] */
  retry (ref) {
    this.remaining++
    this.sent--
    this.outstandingMilli -= toMilli(this.refBets.get(ref) ?? 0)
    if (this.stopReason === 'done') {
      this.stopReason = null
      this.stoppedAt = null
    }
  }

  /** Sends again after a lost connection (the bets left). */
  resume () {
    this.stopReason = null
    this.stoppedAt = null
  }

  /**
   * A drop of this run settled: the profit and the next bet follow.
   * @param {{ bet: number, payout: number, dropId?: number }} result (a drop id counts once)
   * @returns {string | null} the stop reason it caused
   */
  result ({ bet, payout, dropId }) {
    if (dropId !== undefined) {
      if (this.settledIds.has(dropId)) return null
      this.settledIds.add(dropId)
    }
    this.settled++
    this.outstandingMilli -= toMilli(bet)
    this.profitMilli += toMilli(payout) - toMilli(bet)
    const rule = payout > bet ? this.rules.onWin : this.rules.onLoss
    const before = this.bet
    this.bet = rule.mode === 'increase' ? Math.round(this.bet * (1 + rule.percent / 100)) : this.rules.baseBet
    this.log.push({ bet, payout, win: payout > bet, betBefore: before, betAfter: this.bet, profit: this.profit, whileRunning: this.stopReason === null })
    // Only a running run stops on its limits (one that finished sending just settles its last balls).
    if (this.stopReason !== null) return null
    if (this.rules.stopProfit !== null && this.profitMilli >= toMilli(this.rules.stopProfit)) this.stop('profit')
    else if (this.rules.stopLoss !== null && -this.profitMilli >= toMilli(this.rules.stopLoss)) this.stop('loss')
    else return null
    return this.stopReason
  }

  /** @param {AutoBet['stopReason']} reason */
  stop (reason) {
    if (this.stopReason !== null) return
    this.stopReason = reason
    this.stoppedAt = { profit: this.profit, sent: this.sent, settled: this.settled }
  }
}

/**
 * A bet within MIN_BET..MAX_BET and the balance, as a whole number of
 * credits; null when even the minimum is more than the balance.
 * @param {number} bet @param {{ minBet: number, maxBet: number }} limits @param {number | null} balance
 */
export function clampBet (bet, { minBet, maxBet }, balance) {
  const cap = balance === null ? maxBet : Math.min(maxBet, Math.floor(balance))
  if (cap < minBet) return null
  const whole = Number.isFinite(bet) ? Math.round(bet) : minBet
  return Math.max(minBet, Math.min(cap, whole))
}
