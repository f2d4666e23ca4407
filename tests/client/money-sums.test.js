/**
 * The page's running money figures (auto-bet profit and its stops, the
 * session panel's wagered and profit) are exact: summed in milli-credits
 * like the ledger, never as floats of decimals that drift (0.2 − 1 three
 * times is −2.4000000000000004 in floats).
 */
import { describe, it, expect, beforeAll } from 'vitest'
import fc from 'fast-check'
import { AutoBet } from '../../client/auto-bet.js'
import { SessionStats } from '../../client/session-stats.js'
import { payoutMilli, toCredits } from '../../protocol/payout.js'

const limits = { minBet: 1, maxBet: 10_000 }
const rules = (over = {}) => ({ count: 1000, baseBet: 1, stopProfit: null, stopLoss: null, onWin: { mode: 'reset', percent: 0 }, onLoss: { mode: 'reset', percent: 0 }, ...over })
const element = () => ({ textContent: '', className: '', title: '', dataset: {}, setAttribute () {}, removeAttribute (name) { this[name] = '' }, replaceChildren () {} })
const views = () => ({ wagered: element(), profit: element(), drops: element(), best: element(), chart: element() })
/** A settled drop as the server reports it: its payout in credits, at most three decimals. */
const settled = (bet, multiplier) => ({ bet, multiplier, payout: toCredits(payoutMilli(bet, multiplier)) })
const exactProfit = (results) => toCredits(results.reduce((sum, r) => sum + payoutMilli(r.bet, r.multiplier) - r.bet * 1000, 0))
const floatProfit = (results) => results.reduce((sum, r) => sum + r.payout - r.bet, 0)

describe('page money sums', () => {
  beforeAll(() => {
    // The profit chart draws SVG nodes; Node has no document, and the chart is not under test here.
    globalThis.document ??= /** @type {any} */ ({ createElementNS: () => element() })
  })

  it('the session panel shows the exact wagered and profit where a float sum drifts', () => {
    const results = [0.2, 0.2, 0.2].map((m) => settled(1, m))
    expect(floatProfit(results)).not.toBe(-2.4)
    const stats = new SessionStats(views())
    for (const r of results) stats.add(r)
    expect(stats.summary).toMatchObject({ wagered: 3, profit: -2.4, drops: 3, points: 4 })
    // Shown to the cent, the exact figure on hover.
    expect(stats.views.profit.textContent).toBe('−2.40')
    expect(stats.views.profit.title).toBe('exactly −2.4')
  })

  it('auto-bet and the session panel equal the milli-credit sum on any results', () => {
    const result = fc.record({ bet: fc.integer({ min: 1, max: 1000 }), thousandths: fc.integer({ min: 0, max: 1_000_000 }) })
      .map(({ bet, thousandths }) => settled(bet, thousandths / 1000))
    fc.assert(fc.property(fc.array(result, { maxLength: 60 }), (results) => {
      const run = new AutoBet(rules(), limits)
      const stats = new SessionStats(views())
      for (const r of results) { run.result(r); stats.add(r) }
      expect(run.profit).toBe(exactProfit(results))
      expect(stats.profit).toBe(exactProfit(results))
      expect(stats.wagered).toBe(results.reduce((sum, r) => sum + r.bet, 0))
    }), { numRuns: 300 })
  })

  it('stops on profit when the profit reaches the limit, not a float step later', () => {
    const results = [0.2, 0.2, 4.1].map((m) => settled(1, m))
    expect(floatProfit(results)).toBeLessThan(1.5)
    const run = new AutoBet(rules({ stopProfit: 1.5 }), limits)
    expect(results.map((r) => run.result(r))).toEqual([null, null, 'profit'])
    expect(run.profit).toBe(1.5)
  })

  it('stops on loss when the loss reaches the limit', () => {
    const results = [0.2, 0.4, 0.3].map((m) => settled(1, m))
    expect(-floatProfit(results)).toBeLessThan(2.1)
    const run = new AutoBet(rules({ stopLoss: 2.1 }), limits)
    expect(results.map((r) => run.result(r))).toEqual([null, null, 'loss'])
    expect(run.profit).toBe(-2.1)
  })
})
