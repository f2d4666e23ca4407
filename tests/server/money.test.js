import { describe, it, expect } from 'vitest'
import fc from 'fast-check'
import { balanceChanges, RunningBalances, payoutFor, betCost, betTotals, payoutTotals } from '../../server/game/money.js'
import { toLedgerBatch } from '../../server/game/drop.js'
import { calibrationOf, multiplierTable, MIN_ROWS, MAX_ROWS, RISKS } from '../../engine/index.js'

const players = ['a', 'b', 'c']

/** Random batches: drops (bets) and settlements (payouts) of three players, some refused or settled elsewhere. */
const batches = fc.record({
  drops: fc.array(fc.record({ playerId: fc.constantFrom(...players), bet: fc.integer({ min: 1, max: 1000 }), refused: fc.boolean() }), { maxLength: 12 }),
  settlements: fc.array(fc.record({ playerId: fc.constantFrom(...players), payout: fc.integer({ min: 0, max: 100_000 }), elsewhere: fc.boolean() }), { maxLength: 12 }),
  before: fc.tuple(fc.integer({ min: 0, max: 1e9 }), fc.integer({ min: 0, max: 1e9 }), fc.integer({ min: 0, max: 1e9 }))
}).map(({ drops, settlements, before }) => {
  let id = 1
  const d = drops.map((x) => ({ id: id++, playerId: x.playerId, bet: x.bet, refused: x.refused }))
  const s = settlements.map((x) => ({ drop: { id: id++, playerId: x.playerId }, payout: x.payout, elsewhere: x.elsewhere }))
  const outcome = {
    rejected: new Map(d.filter((x) => x.refused).map((x) => [x.id, 'E_INSUFFICIENT_FUNDS'])),
    settled: new Set(s.filter((x) => !x.elsewhere).map((x) => x.drop.id)),
    balances: new Map()
  }
  const start = new Map(players.map((p, i) => [p, before[i]]))
  // What the ledger would hold afterwards: the start plus what it committed.
  for (const p of players) outcome.balances.set(p, start.get(p))
  for (const x of d) if (!x.refused) outcome.balances.set(x.playerId, outcome.balances.get(x.playerId) - x.bet * 1000)
  for (const x of s) if (!x.elsewhere) outcome.balances.set(x.drop.playerId, outcome.balances.get(x.drop.playerId) + x.payout)
  return { drops: d, settlements: s, outcome, start }
})

describe('money rules (server/game/money.js)', () => {
  it('shows each message the balance right after its own change, ending at what the ledger committed', () => {
    fc.assert(fc.property(batches, ({ drops, settlements, outcome, start }) => {
      const running = new RunningBalances(drops, settlements, outcome)
      const shown = new Map(start)
      for (const drop of drops) {
        if (outcome.rejected.has(drop.id)) continue
        shown.set(drop.playerId, shown.get(drop.playerId) - drop.bet * 1000)
        expect(running.apply(drop.playerId, -betCost(drop.bet))).toBe(shown.get(drop.playerId))
      }
      for (const { drop, payout } of settlements) {
        const credited = outcome.settled.has(drop.id) ? payout : 0
        shown.set(drop.playerId, shown.get(drop.playerId) + credited)
        expect(running.apply(drop.playerId, credited)).toBe(shown.get(drop.playerId))
      }
      for (const p of players) if (drops.some((d) => d.playerId === p) || settlements.some((s) => s.drop.playerId === p)) expect(shown.get(p)).toBe(outcome.balances.get(p))
    }))
  })

  it('writes the same net change per player that the messages add up to', () => {
    fc.assert(fc.property(batches, ({ drops, settlements }) => {
      const batch = toLedgerBatch({ drops: drops.map((d) => ({ ...d, seedId: 's', nonce: 0, clientSeedChange: null })), settlements })
      const written = new Map(batch.balances.map((b) => [b.playerId, b.delta]))
      for (const [playerId, change] of balanceChanges(drops, settlements)) expect(written.get(playerId) ?? 0).toBe(change)
      expect(new Set(batch.players)).toEqual(new Set([...drops.map((d) => d.playerId), ...settlements.map((s) => s.drop.playerId)]))
    }))
  })

  it('refuses to guess a balance the ledger did not return', () => {
    const outcome = { rejected: new Map(), settled: new Set(), balances: new Map() }
    expect(() => new RunningBalances([{ id: 1, playerId: 'a', bet: 5 }], [], outcome)).toThrow(/did not return the balance of a/)
  })

  it('pays bet × multiplier exactly in milli-credits, and old drops under the legacy floor rule', () => {
    expect(payoutFor(10, 0.3)).toBe(3000)
    expect(payoutFor(1, 0.1 + 0.2)).toBe(300) // float error does not cost the player
    expect(payoutFor(1, 0.2)).toBe(200)
    expect(payoutFor(1000, 1000)).toBe(1_000_000_000)
    expect(payoutFor(1, 0.3, 1)).toBe(0) // rule 1: floor to whole credits, as 1.0.0 ledgers paid
    expect(payoutFor(7, 1.5, 1)).toBe(10_000)
    expect(() => payoutFor(1, 1, 3)).toThrow(/no payout rule 3/)
  })

  it('returns the advertised RTP at the minimum bet on every table (issue #14: floor rounding once paid 42–72%)', () => {
    for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
      const { drops, bucketCounts, rtp } = calibrationOf(rows)
      for (const risk of RISKS) {
        const table = multiplierTable(rows, risk)
        // Effective return of 1-credit bets on the calibration's own drops, under each rule.
        const returned = (rule) => bucketCounts.reduce((sum, n, b) => sum + n * payoutFor(1, table[b], rule), 0) / 1000 / drops
        expect(Math.abs(returned(2) - rtp[risk]), `${rows}-${risk}`).toBeLessThan(1e-6) // the calibration's RTP is stored rounded
        expect(returned(1), `${rows}-${risk} under the legacy rule`).toBeLessThan(rtp[risk] - 0.05)
      }
    }
  })

  it('totals bets and payouts per player as the shared ledger debits and credits them, agreeing with balanceChanges', () => {
    fc.assert(fc.property(
      fc.array(fc.record({ playerId: fc.constantFrom('a', 'b', 'c'), bet: fc.integer({ min: 1, max: 1000 }) }), { maxLength: 20 }),
      fc.array(fc.record({ playerId: fc.constantFrom('a', 'b', 'c'), payout: fc.integer({ min: 0, max: 1_000_000 }) }), { maxLength: 20 }),
      (drops, landings) => {
        const bets = betTotals(drops)
        const payouts = payoutTotals(landings)
        for (const [, total] of payouts) expect(total).toBeGreaterThan(0)
        const changes = balanceChanges(drops.map((d, id) => ({ ...d, id })), landings.map(({ playerId, payout }, id) => ({ drop: { playerId, id }, payout })))
        for (const player of ['a', 'b', 'c']) expect((payouts.get(player) ?? 0) - (bets.get(player) ?? 0)).toBe(changes.get(player) ?? 0)
      }
    ))
    expect(betTotals([{ playerId: 'a', bet: 10 }, { playerId: 'a', bet: 5 }])).toEqual(new Map([['a', betCost(15)]]))
  })
})
