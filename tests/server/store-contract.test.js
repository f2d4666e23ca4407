import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { createHash } from 'node:crypto'
import { storeBackend, roomSumsOverDrops } from './helpers/stores.js'
import { openStore } from '../../server/store/open-store.js'
import { openSharedLedger } from '../../server/cluster/shared-ledger.js'
import { toLedgerBatch } from '../../server/game/drop.js'
import { payoutFor, toMilli } from '../../server/game/money.js'

/**
 * The ledger contract (server/store/ledger-store.js), one set of checks run
 * against every implementation: SQLite, PostgreSQL, and the cluster's
 * shared PostgreSQL ledger. Batches are built by the game's own
 * toLedgerBatch, so the rows are the ones the server writes.
 */
const IMPLEMENTATIONS = [
  { name: 'SQLite', backend: 'sqlite', open: (database) => openStore(database) },
  { name: 'PostgreSQL', backend: 'postgres', open: (database) => openStore(database) },
  { name: 'shared PostgreSQL ledger (cluster)', backend: 'postgres', open: (database) => openSharedLedger(database) }
]

const sha256 = (text) => createHash('sha256').update(text).digest('hex')
const seedNamed = (name) => ({ id: `seed-${name}`, seed: sha256(`server seed ${name}`), hash: sha256(sha256(`server seed ${name}`)) })

function newPlayer (name, balance) {
  return { id: `player-${name}`, tokenHash: sha256(`token ${name}`), balance: toMilli(balance), clientSeed: `client-${name}`, createdAt: Date.UTC(2026, 11, 1, 12), seed: seedNamed(`${name}-1`) }
}

/** A drop as the game holds it (server/game/drop.js), for toLedgerBatch. */
function gameDrop (id, account, { bet = 10, room = '16-medium', nonce }) {
  return {
    id, account, playerId: account.playerId, roomId: room, rows: 16, risk: 'medium', engineVersion: '2.0.0',
    seedId: account.seed.id, serverSeedHash: account.seed.hash, clientSeed: account.clientSeed, nonce,
    dropSeed: sha256(`drop ${id}`), bet, payoutRule: 1, createdAt: Date.UTC(2026, 11, 1, 12, 0, id), startTick: 100 + id, clientSeedChange: null
  }
}

function settlement (drop, multiplier) {
  return { drop, bucket: 3, multiplier, payout: payoutFor(drop.bet, multiplier), ticks: 180, stateHash: '0123456789abcdef', tick: drop.startTick + 180, settledAt: drop.createdAt + 3000 }
}

describe.each(IMPLEMENTATIONS)('the ledger contract: $name', ({ name, backend: kind, open }) => {
  const backend = storeBackend(kind)
  let store
  let database
  beforeAll(async () => {
    await backend.setup()
    database = (await backend.newDatabase()).database
    store = await open(database)
  }, 120_000)
  afterAll(async () => {
    await store?.close()
    await backend.teardown()
  })

  it('migrates again without change, and starts empty', async () => {
    await store.migrate()
    expect(await store.maxDropId()).toBe(0)
    expect(await store.listInFlightDrops()).toEqual([])
    expect(await store.loadAccount('nobody')).toBeNull()
    expect(await store.findPlayerIdByTokenHash(sha256('no token'))).toBeNull()
    expect(await store.getDrop(1)).toBeNull()
  })

  it('creates a player with its first seed, found by its token hash', async () => {
    const player = newPlayer('ada', 100)
    await store.createPlayer(player)
    expect(await store.findPlayerIdByTokenHash(player.tokenHash)).toBe(player.id)
    const account = await store.loadAccount(player.id)
    expect(account).toMatchObject({ playerId: player.id, balance: toMilli(100), clientSeed: 'client-ada', createdAt: player.createdAt })
    expect(account.seed).toMatchObject({ id: player.seed.id, seed: player.seed.seed, hash: player.seed.hash })
    expect(account.seed.nextNonce).toBe(0)
    const [seed] = await store.listSeeds(player.id)
    expect(seed).toMatchObject({ id: player.seed.id, serverSeedHash: player.seed.hash, active: true, serverSeed: null, revealedAt: null })
    expect(JSON.stringify(await store.listSeeds(player.id))).not.toContain(player.seed.seed)
  })

  it('debits a bet and credits its payout in the batches that record and settle it, and returns the committed balances', async () => {
    const account = await store.loadAccount('player-ada')
    const first = gameDrop(1, account, { bet: 10, nonce: 0 })
    const second = gameDrop(2, account, { bet: 5, nonce: 1, room: '8-low' })
    const recorded = await store.commitBatch(toLedgerBatch({ drops: [first, second], settlements: [] }))
    expect(recorded.rejected.size).toBe(0)
    expect(recorded.balances.get('player-ada')).toBe(toMilli(85))
    expect((await store.listInFlightDrops()).map((d) => d.id)).toEqual([1, 2])
    const inFlight = await store.getDrop(1)
    expect(inFlight).toMatchObject({ id: 1, playerId: 'player-ada', room: '16-medium', bet: 10, nonce: 0, status: 'in_flight', bucket: null, payout: null, startTick: 101 })
    expect(inFlight.serverSeed ?? null).toBeNull()
    expect(await store.getServerSeedOfDrop(1)).toBe(account.seed.seed)
    expect(await store.maxDropId()).toBe(2)

    const settled = await store.commitBatch(toLedgerBatch({ drops: [], settlements: [settlement(first, 2.5)] }))
    expect([...settled.settled]).toEqual([1])
    expect(settled.balances.get('player-ada')).toBe(toMilli(110))
    // Every column of the row, as written by this implementation's statements (server/store/records.js).
    expect(await store.getDrop(1)).toEqual({
      id: 1, playerId: 'player-ada', room: '16-medium', rows: 16, risk: 'medium', engineVersion: '2.0.0', serverSeedHash: account.seed.hash,
      clientSeed: 'client-ada', nonce: 0, dropSeed: first.dropSeed, bet: 10, bucket: 3, multiplier: 2.5, payout: 25, payoutRule: 1,
      startTick: 101, ticks: 180, stateHash: '0123456789abcdef', status: 'settled', serverSeed: null,
      createdAt: new Date(first.createdAt).toISOString(), settledAt: new Date(first.createdAt + 3000).toISOString()
    })
    expect((await store.listInFlightDrops()).map((d) => d.id)).toEqual([2])
    const reloaded = await store.loadAccount('player-ada')
    expect(reloaded.balance).toBe(toMilli(110))
    // A nonce a batch recorded is never handed out again (a cluster's store reserves them in blocks).
    expect(reloaded.seed.nextNonce).toBeGreaterThanOrEqual(2)
  })

  it('never credits a settlement twice', async () => {
    const account = await store.loadAccount('player-ada')
    const first = { ...gameDrop(1, account, { bet: 10, nonce: 0 }) }
    let outcome = null
    try {
      outcome = await store.commitBatch(toLedgerBatch({ drops: [], settlements: [settlement(first, 2.5)] }))
    } catch (error) {
      expect(error.message).toMatch(/not in flight/)
    }
    if (outcome) expect(outcome.settled.has(1)).toBe(false)
    expect((await store.loadAccount('player-ada')).balance).toBe(toMilli(110))
    expect((await store.getDrop(1)).payout).toBe(25)
  })

  it('rotates a seed: the old one revealed on its drops and in the list, the new one active', async () => {
    const before = await store.loadAccount('player-ada')
    const next = seedNamed('ada-2')
    await store.rotateSeed({ playerId: 'player-ada', oldSeedId: before.seed.id, newSeed: next, at: Date.UTC(2026, 11, 1, 13) })
    const after = await store.loadAccount('player-ada')
    expect(after.seed).toMatchObject({ id: next.id, hash: next.hash })
    expect((await store.getDrop(1)).serverSeed).toBe(before.seed.seed)
    const seeds = await store.listSeeds('player-ada')
    expect(seeds.find((s) => s.serverSeedHash === before.seed.hash)).toMatchObject({ active: false, serverSeed: before.seed.seed, revealedAt: new Date(Date.UTC(2026, 11, 1, 13)).toISOString() })
    expect(JSON.stringify(seeds)).toContain(before.seed.seed)
    expect(JSON.stringify(seeds)).not.toContain(next.seed)
    await expect(store.rotateSeed({ playerId: 'player-ada', oldSeedId: before.seed.id, newSeed: seedNamed('ada-3'), at: Date.now() })).rejects.toThrow()
  })

  it('lists drops newest first with a limit, iterates them oldest first, and sums a room', async () => {
    expect((await store.listDrops({ playerId: 'player-ada', limit: 10 })).map((d) => d.id)).toEqual([2, 1])
    expect((await store.listDrops({ playerId: 'player-ada', limit: 1 })).map((d) => d.id)).toEqual([2])
    expect((await store.listDrops({ room: '8-low', limit: 10 })).map((d) => d.id)).toEqual([2])
    expect((await store.listDrops({ playerId: 'someone else', limit: 10 }))).toEqual([])
    const all = []
    for await (const drop of store.iterateDrops({ playerId: 'player-ada' })) all.push(drop.id)
    expect(all).toEqual([1, 2])
    const stats = await store.roomStats('16-medium', '2.0.0')
    expect(JSON.stringify(stats)).toMatch(/25/)
    expect(await store.roomStats('16-medium', '1.0.0')).not.toEqual(stats)
  })

  it("counts a seed's nonces from its recorded drops: the next is one past the highest, and a retired seed keeps its count", async () => {
    // The cluster's ledger reserves nonces in blocks (cluster/shared-ledger.js): its counts are what it reserved, never less.
    const account = await store.loadAccount('player-ada')
    const from = account.seed.nextNonce
    // Nonces from+1..from+5 were taken by drops that were never recorded (refused): the highest recorded counts.
    await store.commitBatch(toLedgerBatch({ drops: [gameDrop(10, account, { nonce: from }), gameDrop(11, account, { nonce: from + 6 })], settlements: [] }))
    const reloaded = (await store.loadAccount('player-ada')).seed.nextNonce
    const listed = (await store.listSeeds('player-ada')).find((s) => s.active).nonce
    for (const count of [reloaded, listed]) {
      expect(count).toBeGreaterThanOrEqual(from + 7)
      if (!name.includes('cluster')) expect(count).toBe(from + 7)
    }
    await store.rotateSeed({ playerId: 'player-ada', oldSeedId: account.seed.id, newSeed: seedNamed('ada-4'), at: Date.UTC(2026, 11, 1, 14) })
    const retired = (await store.listSeeds('player-ada')).find((s) => s.serverSeedHash === account.seed.hash)
    expect(retired).toMatchObject({ active: false })
    expect(retired.nonce).toBeGreaterThanOrEqual(from + 7)
    if (!name.includes('cluster')) expect(retired.nonce).toBe(from + 7)
    if (!name.includes('cluster')) expect((await store.loadAccount('player-ada')).seed.nextNonce).toBe(0)
  })

  it("keeps each room's totals by bucket as its drops settle: the sums over its settled drops, in flight counted apart", async () => {
    await store.createPlayer(newPlayer('bo', 1000))
    const account = await store.loadAccount('player-bo')
    const inRoom = (id, room, bet, engineVersion = '2.0.0') => ({ ...gameDrop(id, account, { bet, room, nonce: id - 20 }), engineVersion })
    const drops = [inRoom(20, '16-medium', 7), inRoom(21, '16-medium', 3), inRoom(22, '16-medium', 2), inRoom(23, '8-low', 4), inRoom(24, '16-medium', 6, '1.0.0'), inRoom(25, '16-medium', 1)]
    await store.commitBatch(toLedgerBatch({ drops, settlements: [] }))
    const landed = (drop, bucket, multiplier) => ({ ...settlement(drop, multiplier), bucket })
    // Two drops of one room and bucket in one batch (added up within it), one in another bucket, another room and another version; 25 stays in flight.
    await store.commitBatch(toLedgerBatch({ drops: [], settlements: [landed(drops[0], 3, 0.5), landed(drops[1], 3, 1.1), landed(drops[2], 9, 5.6), landed(drops[3], 0, 0.3), landed(drops[4], 3, 2)] }))
    for (const [room, engineVersion] of [['16-medium', '2.0.0'], ['16-medium', '1.0.0'], ['8-low', '2.0.0'], ['12-high', '2.0.0']]) {
      const stats = await store.roomStats(room, engineVersion)
      const sums = await roomSumsOverDrops(backend, database, room, engineVersion)
      expect(stats.buckets).toEqual(sums.buckets)
      expect(stats.inFlight).toBe(sums.inFlight)
      expect(stats.settled).toBe(sums.buckets.reduce((n, b) => n + b.count, 0))
    }
    const medium = await store.roomStats('16-medium', '2.0.0')
    // Drop 1 (bucket 3, bet 10, paid 25) and 20 and 21 in bucket 3; 22 in bucket 9; 10, 11 (the nonce test's) and 25 in flight.
    expect(medium.buckets).toEqual([{ bucket: 3, count: 3, bet: 20, payout: 25 + 3.5 + 3.3 }, { bucket: 9, count: 1, bet: 2, payout: 11.2 }])
    expect(medium.inFlight).toBe(3)
    expect(medium.rtp).toBeCloseTo((25 + 3.5 + 3.3 + 11.2) / 22, 12)
    expect((await store.roomStats('12-high', '2.0.0'))).toMatchObject({ settled: 0, inFlight: 0, buckets: [], rtp: null })
  })

  it("lists a player's drops in play order, seed by seed and nonce by nonce, from a page's cursor on, whatever their ids", async () => {
    const collect = async (filter, pageSize) => { const ids = []; for await (const drop of store.iterateDrops(filter, pageSize)) ids.push(drop.id); return ids }
    const ids = async (filter) => (await store.listDrops(filter)).map((d) => d.id)
    await store.createPlayer(newPlayer('eve', 1000))
    await store.createPlayer(newPlayer('gus', 1000))
    const eve = await store.loadAccount('player-eve')
    const gus = await store.loadAccount('player-gus')
    // eve: 70-72 on her first seed, then 73 and 74 (in 8-low) on her second; gus's 75 between them.
    await store.commitBatch(toLedgerBatch({ drops: [70, 71, 72].map((id, n) => gameDrop(id, eve, { nonce: n })), settlements: [] }))
    await store.commitBatch(toLedgerBatch({ drops: [gameDrop(75, gus, { nonce: 0 })], settlements: [] }))
    await store.rotateSeed({ playerId: 'player-eve', oldSeedId: eve.seed.id, newSeed: seedNamed('eve-2'), at: Date.UTC(2026, 11, 1, 13) })
    const eve2 = await store.loadAccount('player-eve')
    await store.commitBatch(toLedgerBatch({ drops: [gameDrop(73, eve2, { nonce: 0 }), gameDrop(74, eve2, { nonce: 1, room: '8-low' })], settlements: [] }))
    // gus's second seed takes lower ids than his first (in a cluster, another process's block of ids): play order still lists it last.
    await store.rotateSeed({ playerId: 'player-gus', oldSeedId: gus.seed.id, newSeed: seedNamed('gus-2'), at: Date.UTC(2026, 11, 1, 13) })
    const gus2 = await store.loadAccount('player-gus')
    await store.commitBatch(toLedgerBatch({ drops: [66, 67].map((id, n) => gameDrop(id, gus2, { nonce: n })), settlements: [] }))

    expect(await ids({ playerId: 'player-eve', limit: 10 })).toEqual([74, 73, 72, 71, 70])
    expect(await ids({ playerId: 'player-eve', limit: 2 })).toEqual([74, 73])
    expect(await ids({ playerId: 'player-eve', beforeId: 73, limit: 2 })).toEqual([72, 71])
    expect(await ids({ playerId: 'player-eve', beforeId: 71, limit: 2 })).toEqual([70])
    expect(await ids({ playerId: 'player-eve', beforeId: 70, limit: 2 })).toEqual([])
    expect(await ids({ playerId: 'player-eve', room: '8-low', limit: 10 })).toEqual([74])
    expect(await ids({ playerId: 'player-eve', room: '16-medium', beforeId: 74, limit: 10 })).toEqual([73, 72, 71, 70])
    expect(await ids({ playerId: 'player-eve', serverSeedHash: eve2.seed.hash, limit: 10 })).toEqual([74, 73])
    // A cursor that is none of her drops has no place in her history: not found, and the same for a seed.
    for (const beforeId of [75, 1, 9999]) {
      await expect(ids({ playerId: 'player-eve', beforeId, limit: 10 })).rejects.toMatchObject({ code: 'E_NOT_FOUND', statusCode: 404 })
    }
    await expect(ids({ serverSeedHash: eve2.seed.hash, beforeId: 72, limit: 10 })).rejects.toMatchObject({ code: 'E_NOT_FOUND' })
    expect(await ids({ playerId: 'player-eve', beforeId: 72, room: '8-low', limit: 10 })).toEqual([])
    expect(await collect({ playerId: 'player-eve' }, 2)).toEqual([70, 71, 72, 73, 74])
    expect(await collect({ playerId: 'player-eve', from: Date.UTC(2026, 11, 1, 12, 1, 11) }, 1)).toEqual([71, 72, 73, 74])

    expect(await ids({ playerId: 'player-gus', limit: 10 })).toEqual([67, 66, 75])
    expect(await ids({ playerId: 'player-gus', beforeId: 66, limit: 10 })).toEqual([75])
    expect(await collect({ playerId: 'player-gus' }, 1)).toEqual([75, 66, 67])
    expect(await collect({ playerId: 'player-gus' }, 10)).toEqual([75, 66, 67])
  })

  it("walks a player's seeds a few at a time: many seeds, ties of creation time, pages across the reads", async () => {
    const collect = async (filter, pageSize) => { const ids = []; for await (const drop of store.iterateDrops(filter, pageSize)) ids.push(drop.id); return ids }
    const ids = async (filter) => (await store.listDrops(filter)).map((d) => d.id)
    await store.createPlayer(newPlayer('hal', 1000))
    let account = await store.loadAccount('player-hal')
    // 40 seeds (the walk reads 16 at a time), two created in each second: ties broken by id.
    // Drops 200.. on two seeds in three, two each (both seeds of some ties); the others stay empty.
    const expected = []
    let id = 200
    for (let k = 0; k < 40; k++) {
      if (k % 3 !== 2) {
        const drops = [id, id + 1].map((dropId, n) => gameDrop(dropId, account, { nonce: n }))
        await store.commitBatch(toLedgerBatch({ drops, settlements: [] }))
        expected.push(id, id + 1)
        id += 2
      }
      if (k < 39) {
        // seed ids in the order of creation within each tie: hal-2a, hal-2b, hal-3a, …
        await store.rotateSeed({ playerId: 'player-hal', oldSeedId: account.seed.id, newSeed: seedNamed(`hal-${2 + (k >> 1)}${'ab'[k & 1]}`), at: Date.UTC(2026, 11, 2) + 1000 * (k >> 1) })
        account = await store.loadAccount('player-hal')
      }
    }
    const newest = [...expected].reverse()
    expect(await ids({ playerId: 'player-hal', limit: 100 })).toEqual(newest)
    // Pages of 3 from each page's last drop: every drop once, in order.
    const paged = []
    let before
    for (;;) {
      const page = await ids({ playerId: 'player-hal', beforeId: before, limit: 3 })
      paged.push(...page)
      if (page.length < 3) break
      before = page[page.length - 1]
    }
    expect(paged).toEqual(newest)
    expect(await collect({ playerId: 'player-hal' }, 4)).toEqual(expected)
    expect(await collect({ playerId: 'player-hal' }, 1000)).toEqual(expected)
  })

  it("pages a seed's drops oldest first and newest first: only that seed's, across pages, another seed and another player's drops between them left out", async () => {
    const collect = async (filter, pageSize) => { const ids = []; for await (const drop of store.iterateDrops(filter, pageSize)) ids.push(drop.id); return ids }
    await store.createPlayer(newPlayer('cy', 1000))
    await store.createPlayer(newPlayer('di', 1000))
    const cy = await store.loadAccount('player-cy')
    const di = await store.loadAccount('player-di')
    const first = cy.seed
    // Drops 40-46 on cy's first seed, di's 50-52 recorded between them.
    await store.commitBatch(toLedgerBatch({ drops: [40, 41, 42].map((id, n) => gameDrop(id, cy, { nonce: n })), settlements: [] }))
    await store.commitBatch(toLedgerBatch({ drops: [50, 51, 52].map((id, n) => gameDrop(id, di, { nonce: n })), settlements: [] }))
    await store.commitBatch(toLedgerBatch({ drops: [43, 44, 45, 46].map((id, n) => gameDrop(id, cy, { nonce: 3 + n })), settlements: [] }))
    await store.rotateSeed({ playerId: 'player-cy', oldSeedId: first.id, newSeed: seedNamed('cy-2'), at: Date.UTC(2026, 11, 1, 15) })
    const second = (await store.loadAccount('player-cy')).seed
    await store.commitBatch(toLedgerBatch({ drops: [60, 61, 62].map((id, n) => gameDrop(id, { ...cy, seed: second }, { nonce: n })), settlements: [] }))

    expect(await collect({ serverSeedHash: first.hash }, 2)).toEqual([40, 41, 42, 43, 44, 45, 46])
    expect(await collect({ serverSeedHash: first.hash }, 7)).toEqual([40, 41, 42, 43, 44, 45, 46])
    expect(await collect({ serverSeedHash: second.hash }, 2)).toEqual([60, 61, 62])
    expect(await collect({ playerId: 'player-cy', serverSeedHash: first.hash }, 3)).toEqual([40, 41, 42, 43, 44, 45, 46])
    expect(await collect({ playerId: 'player-di', serverSeedHash: first.hash }, 3)).toEqual([])
    expect(await collect({ serverSeedHash: di.seed.hash }, 2)).toEqual([50, 51, 52])
    expect(await collect({ serverSeedHash: 'f'.repeat(64) }, 2)).toEqual([])
    expect((await store.listDrops({ serverSeedHash: first.hash, limit: 3 })).map((d) => d.id)).toEqual([46, 45, 44])
    expect((await store.listDrops({ serverSeedHash: first.hash, beforeId: 44, limit: 10 })).map((d) => d.id)).toEqual([43, 42, 41, 40])
    expect((await store.listDrops({ serverSeedHash: first.hash, nonce: 2, limit: 10 })).map((d) => d.id)).toEqual([42])
    expect((await store.listDrops({ serverSeedHash: second.hash, nonce: 2, limit: 10 })).map((d) => d.id)).toEqual([62])
  })
})
