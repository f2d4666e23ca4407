import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { storeBackend } from './helpers/stores.js'
import { openStore } from '../../server/store/open-store.js'
import { LISTING_POOL_SIZE } from '../../server/store/postgres-store.js'

/**
 * The PostgreSQL store's listings of drops run on connections of their
 * own (server/store/postgres-store.js `listingPool`): however many
 * listings hold them, and for however long, a tick's commit still gets a
 * connection and goes through.
 */
describe('the PostgreSQL ledger\'s listings', () => {
  const backend = storeBackend('postgres')
  let store
  beforeAll(async () => {
    await backend.setup()
    store = await openStore((await backend.newDatabase()).database)
    await store.createPlayer({ id: 'p1', tokenHash: 'h1', balance: 1_000_000, clientSeed: 'c', createdAt: 1, seed: { id: 's1', seed: 'a'.repeat(64), hash: 'b'.repeat(64) } })
  }, 120_000)
  afterAll(async () => {
    await store?.close()
    await backend.teardown()
  })

  const drop = (id) => ({ id, playerId: 'p1', room: '8-low', rows: 8, risk: 'low', engineVersion: '1.0.0', serverSeedId: 's1', serverSeedHash: 'b'.repeat(64), clientSeed: 'c', nonce: id, dropSeed: 'd'.repeat(64), bet: 10, payoutRule: 2, startTick: 0, createdAt: 2 })
  const batch = (drops) => ({ drops, settlements: [], balances: [{ playerId: 'p1', delta: -10_000 * drops.length }], clientSeeds: [], players: ['p1'] })

  it('commits while every listing connection is taken, and the listing waiting for one goes through once one is free', async () => {
    await store.commitBatch(batch([drop(1)]))
    const held = []
    for (let i = 0; i < LISTING_POOL_SIZE; i++) held.push(await store.listingPool.connect())
    let listed = null
    const listing = store.listDrops({ playerId: 'p1', limit: 10 }).then((drops) => { listed = drops })
    const outcome = await store.commitBatch(batch([drop(2), drop(3)]))
    expect(outcome.balances.get('p1')).toBe(1_000_000 - 30_000)
    // The listing still waits for a connection of its own.
    expect(listed).toBeNull()
    expect(store.listingPool.waitingCount).toBe(1)
    for (const client of held) client.release()
    await listing
    expect(listed.map((d) => d.id)).toEqual([3, 2, 1])
  })
})
