import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { createBoard, simulateDrop } from '../../engine/index.js'
import { startPostgres } from '../../tools/postgres-process.js'
import { openSharedLedger } from '../../server/cluster/shared-ledger.js'
import { ClusterSequences } from '../../server/cluster/cluster-sequences.js'
import { settleInterruptedDrops } from '../../server/game/recovery.js'

const silentLog = { info () {}, warn () {}, error () {} }

/** The shared ledger against a real PostgreSQL: two stores = two processes. */
describe('shared ledger (clustered PostgreSQL store)', () => {
  let postgres
  beforeAll(async () => { postgres = await startPostgres() })
  afterAll(async () => { await postgres?.stop() })

  async function twoProcesses () {
    const url = await postgres.createDatabase()
    const a = await openSharedLedger({ url })
    const b = await openSharedLedger({ url })
    const seed = { id: 's1', seed: 'seed-1', hash: 'h'.repeat(64) }
    // The store takes milli-credits: 100 credits. Bets are whole credits.
    await a.createPlayer({ id: 'p1', tokenHash: 't'.repeat(64), balance: 100_000, clientSeed: 'c', createdAt: 1, seed })
    return { a, b, close: async () => { await a.close(); await b.close() } }
  }

  const dropRow = (id, nonce, bet, extra = {}) => ({
    id, playerId: 'p1', room: '8-low', rows: 8, risk: 'low', engineVersion: createBoard({ rows: 8, risk: 'low' }).engineVersion,
    serverSeedId: 's1', serverSeedHash: 'h'.repeat(64), clientSeed: 'c', nonce, dropSeed: `seed-${id}`, bet, payoutRule: 2, startTick: 0, createdAt: 2, ...extra
  })
  const batch = (drops, settlements = []) => ({ drops, settlements, balances: [], nonces: [], clientSeeds: [] })

  it('reserves disjoint drop id and nonce blocks per process (handed out by each one\'s sequences)', async () => {
    const { a: storeA, b: storeB, close } = await twoProcesses()
    try {
      const [a, b] = [new ClusterSequences({ store: storeA }), new ClusterSequences({ store: storeB })]
      await a.start()
      await b.start()
      const idsA = [a.takeDropId(), a.takeDropId()]
      const idsB = [b.takeDropId(), b.takeDropId()]
      expect(new Set([...idsA, ...idsB]).size).toBe(4)
      const accountA = await storeA.loadAccount('p1')
      const accountB = await storeB.loadAccount('p1')
      const noncesA = [a.takeNonce(accountA.seed), a.takeNonce(accountA.seed)]
      const noncesB = [b.takeNonce(accountB.seed), b.takeNonce(accountB.seed)]
      expect(new Set([...noncesA, ...noncesB]).size).toBe(4)
    } finally { await close() }
  })

  it('debits only what the balance covers: one batch per process, the second is refused', async () => {
    const { a, b, close } = await twoProcesses()
    try {
      const first = await a.commitBatch(batch([dropRow(1, 0, 80)]))
      const second = await b.commitBatch(batch([dropRow(2, 1000, 80)]))
      expect(first.rejected.size).toBe(0)
      expect(first.balances.get('p1')).toBe(20_000)
      expect([...second.rejected]).toEqual([[2, 'E_INSUFFICIENT_FUNDS']])
      expect(second.balances.get('p1')).toBe(20_000)
      expect((await a.listInFlightDrops()).map((d) => d.id)).toEqual([1])
    } finally { await close() }
  })

  it('settles a drop once when two processes recover it at the same time', async () => {
    const { a, b, close } = await twoProcesses()
    try {
      await a.commitBatch(batch([dropRow(1, 0, 50), dropRow(2, 1, 50)]))
      const drops = await a.listInFlightDropsOfRoom('8-low')
      const [ra, rb] = await Promise.all([
        settleInterruptedDrops(a, silentLog, { drops }),
        settleInterruptedDrops(b, silentLog, { drops })
      ])
      expect(ra.settled + rb.settled).toBe(2)
      const board = createBoard({ rows: 8, risk: 'low' })
      const payout = (id) => 50 * Math.round(simulateDrop(board, `seed-${id}`).multiplier * 1000) // milli-credits, exact
      const { balance } = await a.loadAccount('p1')
      expect(balance).toBe(payout(1) + payout(2))
      expect(await a.listInFlightDrops()).toEqual([])
    } finally { await close() }
  })

  it('refuses drops on a seed another process has rotated (revealed)', async () => {
    const { a, b, close } = await twoProcesses()
    try {
      await a.loadAccount('p1')
      await b.rotateSeed({ playerId: 'p1', oldSeedId: 's1', newSeed: { id: 's2', seed: 'seed-2', hash: 'k'.repeat(64) }, at: 3 })
      const result = await a.commitBatch(batch([dropRow(1, 0, 10)]))
      expect([...result.rejected]).toEqual([[1, 'E_SEED_ROTATED']])
      expect(result.balances.get('p1')).toBe(100_000)
    } finally { await close() }
  })
})
