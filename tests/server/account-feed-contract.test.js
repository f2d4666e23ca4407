import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { MODES, coordinationTestbed, itWithOtherProcesses, createPlayer } from './helpers/coordination.js'
import { AccountBook } from '../../server/game/accounts.js'
import { newServerSeed } from '../../server/fairness/seeds.js'
import { toLedgerBatch } from '../../server/game/drop.js'
import { eventually } from '../../tools/eventually.js'
import Redis from 'ioredis'
import { BALANCE_CHANNEL } from '../../server/cluster/balance-sync.js'
import { SEED_CHANNEL, SEED_ACK_CHANNEL } from '../../server/cluster/seed-sync.js'

/**
 * The account feed contract (server/coordination/account-feed.js), run
 * against both modes with real account books. Alone nobody else changes an
 * account; clustered, a balance committed or a seed rotated by one process
 * reaches the account another holds (a rotation before it is answered).
 */
const LIMITS = { dropRate: 10, dropBurst: 10, joinRate: 10 }

describe.each(MODES)('the account feed contract: $name', (entry) => {
  const testbed = coordinationTestbed(entry)
  beforeAll(() => testbed.setup(), 120_000)
  afterAll(() => testbed.teardown(), 60_000)

  /** A process with a started feed, its account book and a player's account held in it. */
  async function holding (playerId, process) {
    process ??= await testbed.process()
    const balanceChanges = []
    const accounts = new AccountBook({ store: process.store, limits: LIMITS })
    await process.feed.start({ accounts, onBalanceChanged: (account, balance) => balanceChanges.push({ playerId: account.playerId, balance }) })
    const account = await accounts.acquire(playerId)
    return { ...process, accounts, account, balanceChanges }
  }

  const activeSeedId = async (store, playerId) => (await store.listSeeds(playerId)).find((seed) => seed.active).id

  it('announces committed balances and rotations without failing the caller', async () => {
    const playerId = await createPlayer((await testbed.process()).store, 'quiet')
    const one = await holding(playerId)
    expect(() => one.feed.balancesCommitted([playerId])).not.toThrow()
    const old = one.account.seed
    const fresh = newServerSeed()
    await one.store.rotateSeed({ playerId, oldSeedId: old.id, newSeed: fresh, at: Date.now() })
    one.account.seed = { ...fresh, nextNonce: 0 }
    await expect(one.feed.seedRotated(one.account)).resolves.toBeUndefined()
    expect(one.account.seed.id).toBe(await activeSeedId(one.store, playerId))
  })

  it('leaves an account on the ledger\'s active seed after seedOutdated, and never rejects', async () => {
    const first = await testbed.process()
    const playerId = await createPlayer(first.store, 'outdated')
    const one = await holding(playerId, first)
    if (entry.redis) {
      // Rotated by another process on the same ledger, its notice never sent.
      const other = await testbed.process()
      const state = await other.store.loadAccount(playerId)
      await other.store.rotateSeed({ playerId, oldSeedId: state.seed.id, newSeed: newServerSeed(), at: Date.now() })
    }
    await expect(one.feed.seedOutdated(one.account)).resolves.toBeUndefined()
    expect(one.account.seed.id).toBe(await activeSeedId(one.store, playerId))
  })

  itWithOtherProcesses(entry)('reports the balance another process committed for an account held here (onBalanceChanged)', async () => {
    const a = await testbed.process()
    const playerId = await createPlayer(a.store, 'balance', 100)
    const here = await holding(playerId, a)
    const there = await holding(playerId)
    const drop = ledgerDrop(1_000_001, here.account, here.account.seed.nextNonce)
    const { balances } = await a.store.commitBatch(toLedgerBatch({ drops: [drop], settlements: [] }))
    here.feed.balancesCommitted([playerId])
    await eventually(() => there.balanceChanges.length > 0)
    expect(there.balanceChanges).toEqual([{ playerId, balance: balances.get(playerId) }])
    expect(here.balanceChanges).toEqual([])
  })

  itWithOtherProcesses(entry)('ignores anything on the notice channels that is no notice, and goes on delivering', async () => {
    const a = await testbed.process()
    const playerId = await createPlayer(a.store, 'garbled', 100)
    const here = await holding(playerId, a)
    const there = await holding(playerId)
    const publisher = new Redis(testbed.redis().url)
    const uncaught = []
    const onUncaught = (error) => uncaught.push(error)
    process.on('uncaughtException', onUncaught)
    try {
      for (const channel of [BALANCE_CHANNEL, SEED_CHANNEL, SEED_ACK_CHANNEL]) {
        for (const text of ['null', '[1]', '42', 'not json', '{"players":5}', '{"id":7}']) await publisher.publish(channel, text)
      }
      const drop = ledgerDrop(1_000_002, here.account, here.account.seed.nextNonce)
      const { balances } = await a.store.commitBatch(toLedgerBatch({ drops: [drop], settlements: [] }))
      here.feed.balancesCommitted([playerId])
      await eventually(() => there.balanceChanges.length > 0)
      expect(there.balanceChanges).toEqual([{ playerId, balance: balances.get(playerId) }])
      expect(uncaught).toEqual([])
    } finally {
      process.off('uncaughtException', onUncaught)
      await publisher.quit()
    }
  })

  itWithOtherProcesses(entry)('answers a rotation only once another process holding the account uses the new seed', async () => {
    const a = await testbed.process()
    const playerId = await createPlayer(a.store, 'rotation')
    const here = await holding(playerId, a)
    const there = await holding(playerId)
    const fresh = newServerSeed()
    await a.store.rotateSeed({ playerId, oldSeedId: here.account.seed.id, newSeed: fresh, at: Date.now() })
    here.account.seed = { ...fresh, nextNonce: 0 }
    await here.feed.seedRotated(here.account)
    expect(there.account.seed.id).toBe(fresh.id)
  })
})

/** A drop as the game holds it (server/game/drop.js), for toLedgerBatch. */
function ledgerDrop (id, account, nonce) {
  return {
    id, account, playerId: account.playerId, roomId: '16-medium', rows: 16, risk: 'medium', engineVersion: '2.0.0',
    seedId: account.seed.id, serverSeedHash: account.seed.hash, clientSeed: account.clientSeed, nonce,
    dropSeed: 'b'.repeat(64), bet: 7, payoutRule: 1, createdAt: Date.now(), startTick: 1, clientSeedChange: null
  }
}
