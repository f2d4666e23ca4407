import { describe, it, expect } from 'vitest'
import fc from 'fast-check'
import { balanceChanges, RunningBalances, payoutFor } from '../../server/game/money.js'
import { toLedgerBatch } from '../../server/game/ledger-batch.js'

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
  for (const x of d) if (!x.refused) outcome.balances.set(x.playerId, outcome.balances.get(x.playerId) - x.bet)
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
        shown.set(drop.playerId, shown.get(drop.playerId) - drop.bet)
        expect(running.apply(drop.playerId, -drop.bet)).toBe(shown.get(drop.playerId))
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

  it('pays integer thousandths of the multiplier, rounded down', () => {
    expect(payoutFor(10, 0.3)).toBe(3)
    expect(payoutFor(3, 0.1 + 0.2)).toBe(0)
    expect(payoutFor(1000, 1000)).toBe(1_000_000)
  })
})
