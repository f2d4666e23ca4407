import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { MODES, coordinationTestbed, itWithOtherProcesses, createPlayer, takeWhenReady } from './helpers/coordination.js'
import { toLedgerBatch } from '../../server/game/drop.js'

/**
 * The sequences contract (server/coordination/sequences.js), run against
 * both modes: drop ids and nonces come from one place, never twice, and a
 * process started later never hands out one already recorded.
 */
describe.each(MODES)('the sequences contract: $name', (entry) => {
  const testbed = coordinationTestbed(entry)
  beforeAll(() => testbed.setup(), 120_000)
  afterAll(() => testbed.teardown(), 60_000)

  it('hands out increasing drop ids, never twice, continuing above the ledger\'s highest', async () => {
    const first = await testbed.process()
    await first.sequences.start()
    const ids = []
    for (let i = 0; i < 50; i++) ids.push(await takeWhenReady(() => first.sequences.takeDropId()))
    expect(ids.every((id, i) => Number.isSafeInteger(id) && id > 0 && (i === 0 || id > ids[i - 1]))).toBe(true)

    // One of them recorded in the ledger: a process started now continues above it.
    const playerId = await createPlayer(first.store, 'ids')
    const account = await first.store.loadAccount(playerId)
    const nonce = first.sequences.takeNonce(account.seed)
    const last = ids.at(-1)
    await first.store.commitBatch(toLedgerBatch({ drops: [recordedDrop(last, account, nonce)], settlements: [] }))
    const next = await testbed.process()
    await next.sequences.start()
    expect(next.sequences.takeDropId()).toBeGreaterThan(last)
  })

  it('hands out a seed\'s nonces from the loaded one on, never twice, past a block of them', async () => {
    const process = await testbed.process()
    await process.sequences.start()
    const playerId = await createPlayer(process.store, 'nonces')
    const account = await process.store.loadAccount(playerId)
    const from = account.seed.nextNonce
    const nonces = []
    for (let i = 0; i < 250; i++) nonces.push(await takeWhenReady(() => process.sequences.takeNonce(account.seed)))
    expect(nonces[0]).toBe(from)
    expect(new Set(nonces).size).toBe(nonces.length)
    expect(nonces.every((n, i) => i === 0 || n > nonces[i - 1])).toBe(true)
  })

  it('never hands out a nonce recorded by an earlier process', async () => {
    const first = await testbed.process()
    await first.sequences.start()
    const playerId = await createPlayer(first.store, 'restart')
    const account = await first.store.loadAccount(playerId)
    const nonces = [first.sequences.takeNonce(account.seed), first.sequences.takeNonce(account.seed)]
    const id = first.sequences.takeDropId()
    await first.store.commitBatch(toLedgerBatch({ drops: [recordedDrop(id, account, nonces[1])], settlements: [] }))
    const next = await testbed.process()
    await next.sequences.start()
    const reloaded = await next.store.loadAccount(playerId)
    expect(next.sequences.takeNonce(reloaded.seed)).toBeGreaterThan(nonces[1])
  })

  itWithOtherProcesses(entry)('never hands out one id or nonce twice across two processes on one ledger', async () => {
    const [a, b] = [await testbed.process(), await testbed.process()]
    await a.sequences.start()
    await b.sequences.start()
    const playerId = await createPlayer(a.store, 'two')
    const [seedA, seedB] = [(await a.store.loadAccount(playerId)).seed, (await b.store.loadAccount(playerId)).seed]
    const ids = []
    const nonces = []
    for (let i = 0; i < 150; i++) {
      ids.push(await takeWhenReady(() => a.sequences.takeDropId()), await takeWhenReady(() => b.sequences.takeDropId()))
      nonces.push(await takeWhenReady(() => a.sequences.takeNonce(seedA)), await takeWhenReady(() => b.sequences.takeNonce(seedB)))
    }
    expect(new Set(ids).size).toBe(ids.length)
    expect(new Set(nonces).size).toBe(nonces.length)
  })
})

/** A drop as the game holds it (server/game/drop.js), for toLedgerBatch. */
function recordedDrop (id, account, nonce) {
  return {
    id, account, playerId: account.playerId, roomId: '16-medium', rows: 16, risk: 'medium', engineVersion: '2.0.0',
    seedId: account.seed.id, serverSeedHash: account.seed.hash, clientSeed: account.clientSeed, nonce,
    dropSeed: 'a'.repeat(64), bet: 1, payoutRule: 1, createdAt: Date.now(), startTick: 1, clientSeedChange: null
  }
}
