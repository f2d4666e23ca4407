/**
 * Auto-bet's stop rules against results that arrive out of step with the
 * sending: a run stops on its limits only while it is sending; the balls
 * still falling when it stopped (it sent its last bet, or a limit stopped
 * it) settle into its log marked as after the stop, and stop nothing.
 */
import { describe, it, expect } from 'vitest'
import { AutoBet } from '../../client/auto-bet.js'

const limits = { minBet: 1, maxBet: 10_000 }
const rules = (over = {}) => ({ count: 3, baseBet: 10, stopProfit: null, stopLoss: 15, onWin: { mode: 'reset', percent: 0 }, onLoss: { mode: 'increase', percent: 100 }, ...over })
const lose = (bet) => ({ bet, payout: 0 })

describe('auto-bet stops', () => {
  it('stops on loss while sending; results after that are logged as after the stop', () => {
    const run = new AutoBet(rules({ count: 10 }), limits)
    for (let i = 0; i < 3; i++) run.markSent(`r${i}`)
    expect(run.result(lose(10))).toBe(null)
    expect(run.result(lose(10))).toBe('loss')
    expect(run.result(lose(10))).toBe(null)
    expect(run.stopReason).toBe('loss')
    expect(run.log.map((e) => [e.whileRunning, -e.profit])).toEqual([[true, 10], [true, 20], [false, 30]])
  })

  it('is done once its last bet is sent: a limit crossed afterwards by a falling ball changes nothing', () => {
    const run = new AutoBet(rules({ count: 3 }), limits)
    for (let i = 0; i < 3; i++) run.markSent(`r${i}`)
    expect(run.stopReason).toBe('done')
    expect([run.result(lose(10)), run.result(lose(10)), run.result(lose(10))]).toEqual([null, null, null])
    expect(run.stopReason).toBe('done')
    expect(run.log.every((e) => !e.whileRunning)).toBe(true)
    expect(run.profit).toBe(-30)
  })

  it('knows where it stopped and when its result is final (every sent ball settled)', () => {
    const run = new AutoBet(rules({ count: 10, stopLoss: null, stopProfit: 5 }), limits)
    for (let i = 0; i < 3; i++) run.markSent(`r${i}`, 10)
    expect(run.result({ bet: 10, payout: 20, dropId: 1 })).toBe('profit')
    expect(run.stoppedAt).toEqual({ profit: 10, sent: 3, settled: 1 })
    expect([run.inFlight, run.finished]).toEqual([2, false])
    run.result({ bet: 10, payout: 0, dropId: 2 })
    run.result({ bet: 10, payout: 0, dropId: 2 })
    expect([run.inFlight, run.finished]).toEqual([1, false])
    run.result({ bet: 10, payout: 0, dropId: 3 })
    expect([run.inFlight, run.finished, run.profit]).toEqual([0, true, -10])
  })

  it('with the guard, holds a bet back while it could take the loss past the limit, and stops when it could alone', () => {
    const run = new AutoBet(rules({ count: 10, stopLoss: 25, guard: true, onLoss: { mode: 'reset', percent: 0 } }), limits)
    expect(run.guardBet(10)).toBe('send')
    run.markSent('r0', 10)
    run.markSent('r1', 10)
    expect(run.guardBet(10)).toBe('wait')
    run.result({ bet: 10, payout: 0 })
    run.result({ bet: 10, payout: 5 })
    expect(run.guardBet(10)).toBe('send')
    run.markSent('r2', 10)
    run.result({ bet: 10, payout: 4 })
    expect(run.profit).toBe(-21)
    expect(run.guardBet(10)).toBe('stop')
    expect(run.guardBet(4)).toBe('send')
    expect(new AutoBet(rules({ stopLoss: 25 }), limits).guardBet(100)).toBe('send')
  })
})
