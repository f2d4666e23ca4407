import { describe, it, expect } from 'vitest'
import { GroupCommit, toLedgerBatch } from '../../server/game/drop.js'
import { createMetrics } from '../../server/metrics.js'

/** A store whose commits the test resolves or rejects one at a time. */
function manualStore () {
  const pending = []
  let active = 0
  let maxActive = 0
  return {
    pending,
    get maxActive () { return maxActive },
    commitBatch (batch) {
      active++
      maxActive = Math.max(maxActive, active)
      return new Promise((resolve, reject) => pending.push({ batch, resolve: () => { active--; resolve() }, reject: (e) => { active--; reject(e) } }))
    }
  }
}

const drop = (id, playerId = 'p', extra = {}) => ({ id, playerId, roomId: '8-low', rows: 8, risk: 'low', engineVersion: 'v', seedId: 's-' + playerId, serverSeedHash: 'h', clientSeed: 'c', nonce: id, dropSeed: 'd' + id, bet: 10 * id, startTick: id, createdAt: 0, clientSeedChange: null, void: false, ...extra })
/** What the server hands every GroupCommit besides its store: metrics and a log. */
const services = () => ({ metrics: createMetrics({ defaultMetrics: false }), log: { error () {} } })
const flushMicrotasks = () => new Promise((resolve) => setImmediate(resolve))

describe('GroupCommit', () => {
  it('writes one transaction per tick, strictly in order, one at a time, and reports each after it commits', async () => {
    const store = manualStore()
    const events = []
    const ledger = new GroupCommit({ ...services(), store, onCommitted: (b) => events.push(['ok', b.drops.map((d) => d.id)]), onFailed: (b) => events.push(['failed', b.drops.map((d) => d.id)]) })
    ledger.addDrop(drop(1))
    ledger.addDrop(drop(2))
    ledger.flush()
    ledger.flush() // nothing new: no empty transaction
    ledger.addDrop(drop(3))
    ledger.flush()
    const job = ledger.run(async () => { events.push(['job']); return 42 })
    ledger.addDrop(drop(4))
    ledger.flush()
    await flushMicrotasks()
    expect(store.pending).toHaveLength(1)
    expect(store.pending[0].batch.drops.map((d) => d.id)).toEqual([1, 2])
    expect(events).toEqual([])
    store.pending[0].resolve()
    await flushMicrotasks()
    store.pending[1].reject(new Error('disk full'))
    expect(await job).toBe(42)
    await flushMicrotasks()
    store.pending[2].resolve()
    await ledger.drain()
    expect(events).toEqual([['ok', [1, 2]], ['failed', [3]], ['job'], ['ok', [4]]])
    expect(store.maxActive).toBe(1)
  })

  it('merges the ticks that end while a slow commit runs into the next transaction', async () => {
    const store = manualStore()
    const committed = []
    const ledger = new GroupCommit({ ...services(), store, onCommitted: (b) => committed.push(b.drops.map((d) => d.id)), onFailed: () => {} })
    ledger.addDrop(drop(1))
    ledger.flush() // tick 1: written at once
    for (let tick = 2; tick <= 4; tick++) {
      ledger.addDrop(drop(tick))
      ledger.flush() // ticks 2..4 end while tick 1 is being written
    }
    await flushMicrotasks()
    expect(store.pending).toHaveLength(1)
    store.pending[0].resolve()
    await flushMicrotasks()
    expect(store.pending).toHaveLength(2)
    expect(store.pending[1].batch.drops.map((d) => d.id)).toEqual([2, 3, 4])
    store.pending[1].resolve()
    await ledger.drain()
    expect(committed).toEqual([[1], [2, 3, 4]])
  })

  it('gathers ticksPerCommit ticks a transaction, never splitting one; a job, the cap or a drain seals it at once', async () => {
    const store = manualStore()
    const committed = []
    const ledger = new GroupCommit({ ...services(), store, ticksPerCommit: 3, maxMergedEntries: 5, onCommitted: (b) => committed.push(b.drops.map((d) => d.id)), onFailed: () => {} })
    const tick = async (...ids) => {
      for (const id of ids) ledger.addDrop(drop(id))
      ledger.flush()
      await flushMicrotasks()
    }
    await tick(1)
    await tick(2, 3)
    expect(store.pending).toHaveLength(0) // two ticks gathered of three
    await tick(4)
    expect(store.pending.map((p) => p.batch.drops.map((d) => d.id))).toEqual([[1, 2, 3, 4]])
    store.pending[0].resolve()
    await tick(5)
    await tick() // an empty tick counts: the clock, not the drops, decides
    await tick()
    expect(store.pending.map((p) => p.batch.drops.map((d) => d.id))).toEqual([[1, 2, 3, 4], [5]])
    store.pending[1].resolve()
    await tick(6, 7, 8)
    await tick(9, 10) // five entries: the cap seals it before its third tick
    expect(store.pending.map((p) => p.batch.drops.map((d) => d.id)).slice(2)).toEqual([[6, 7, 8, 9, 10]])
    store.pending[2].resolve()
    await tick(11)
    const job = ledger.run(async () => 'rotated') // a seed rotation is written after drop 11, not two ticks later
    await flushMicrotasks()
    expect(store.pending.map((p) => p.batch.drops.map((d) => d.id)).slice(3)).toEqual([[11]])
    store.pending[3].resolve()
    expect(await job).toBe('rotated')
    await tick(12)
    const drained = ledger.drain()
    await flushMicrotasks()
    store.pending[4].resolve()
    await drained
    expect(committed).toEqual([[1, 2, 3, 4], [5], [6, 7, 8, 9, 10], [11], [12]])
  })

  it('stops merging at maxMergedEntries: the ticks a long stall held queue as several transactions, in order', async () => {
    const store = manualStore()
    const committed = []
    const ledger = new GroupCommit({ ...services(), store, maxMergedEntries: 3, onCommitted: (b) => committed.push(b.drops.map((d) => d.id)), onFailed: () => {} })
    const settlement = (id) => ({ drop: drop(id), bucket: 0, multiplier: 1, payout: 0, ticks: 1, stateHash: 'x', settledAt: 0 })
    ledger.addDrop(drop(1))
    ledger.flush() // tick 1: written at once, then stalls
    for (let tick = 2; tick <= 6; tick++) {
      ledger.addDrop(drop(tick))
      if (tick === 3) ledger.addSettlement(settlement(1)) // settlements count towards the cap
      ledger.flush()
    }
    await flushMicrotasks()
    expect(store.pending).toHaveLength(1)
    store.pending[0].resolve()
    await flushMicrotasks()
    // ticks 2 and 3 hold three entries: sealed at the cap; 4 to 6 go on merging
    expect(store.pending.map((p) => p.batch.drops.map((d) => d.id))).toEqual([[1], [2, 3]])
    expect(store.pending[1].batch.settlements.map((s) => s.id)).toEqual([1])
    store.pending[1].resolve()
    await flushMicrotasks()
    expect(store.pending.map((p) => p.batch.drops.map((d) => d.id))).toEqual([[1], [2, 3], [4, 5, 6]])
    store.pending[2].resolve()
    await ledger.drain()
    expect(committed).toEqual([[1], [2, 3], [4, 5, 6]])
    expect(store.maxActive).toBe(1)
  })

  it('drops settlements of drops whose own record failed', async () => {
    const store = manualStore()
    const committed = []
    const ledger = new GroupCommit({ ...services(), store, onCommitted: (b) => committed.push(b), onFailed: () => {} })
    const voided = drop(1, 'p', { void: true })
    ledger.addSettlement({ drop: voided, bucket: 0, multiplier: 1, payout: 1, ticks: 1, stateHash: 'x', settledAt: 0, attempts: 0 })
    ledger.addSettlement({ drop: drop(2), bucket: 0, multiplier: 1, payout: 1, ticks: 1, stateHash: 'x', settledAt: 0, attempts: 0 })
    ledger.flush()
    await flushMicrotasks()
    expect(store.pending[0].batch.settlements.map((s) => s.id)).toEqual([2])
    store.pending[0].resolve()
    await ledger.drain()
    expect(committed).toHaveLength(1)
  })

  it('nets balances per player; a drop\'s row is its nonce\'s record (no nonce rows)', () => {
    const rows = toLedgerBatch({
      drops: [drop(1, 'a'), drop(2, 'a', { clientSeedChange: { previous: 'c0' }, clientSeed: 'new' }), drop(3, 'b')],
      settlements: [{ drop: drop(9, 'a'), bucket: 1, multiplier: 2, payout: 500, ticks: 100, stateHash: 'ff', settledAt: 5 }]
    })
    // Milli-credits: a bet of 10 credits costs 10,000; the payout is already milli-credits.
    expect(rows.balances).toEqual([{ playerId: 'a', delta: -10_000 - 20_000 + 500 }, { playerId: 'b', delta: -30_000 }])
    expect(rows).not.toHaveProperty('nonces')
    expect(rows.drops.map((d) => [d.serverSeedId, d.nonce])).toEqual([['s-a', 1], ['s-a', 2], ['s-b', 3]])
    expect(rows.clientSeeds).toEqual([{ playerId: 'a', clientSeed: 'new' }])
    expect(rows.settlements).toEqual([{ id: 9, bucket: 1, multiplier: 2, payout: 500, ticks: 100, stateHash: 'ff', settledAt: 5 }])
    expect(rows.drops[0]).toMatchObject({ id: 1, room: '8-low', serverSeedId: 's-a', dropSeed: 'd1' })
  })
})
