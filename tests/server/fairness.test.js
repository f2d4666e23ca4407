import { describe, it, expect, beforeAll } from 'vitest'
import { createHash, createHmac } from 'node:crypto'
import { verifyDrop } from '../../engine/index.js'
import { STORE_KINDS } from './helpers/stores.js'
import { useServerOn } from './helpers/server.js'

const sha256 = (text) => createHash('sha256').update(text).digest('hex')
const hmac = (key, message) => createHmac('sha256', key).update(message).digest('hex')

describe.each(STORE_KINDS)('provably fair seeds on %s', (kind) => {
  const context = useServerOn(kind)
  const backend = context.backend
  let server
  let database
  beforeAll(() => { ({ server, database } = context) })

  async function dropAndSettle (client, request) {
    client.send({ type: 'drop', ...request })
    const dropped = await client.take('dropped')
    const settled = await client.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    return { dropped, settled }
  }

  it('reveals on rotation a seed that matches the commitment and derives every stored drop seed', async () => {
    const { session, client, token } = await server.player('14-low')
    const commitment = session.serverSeedHash
    for (let i = 0; i < 3; i++) client.send({ type: 'drop', bet: 10 + i })
    const plays = []
    for (let i = 0; i < 3; i++) plays.push({ dropped: await client.take('dropped') })
    for (const play of plays) play.settled = await client.take((m) => m.type === 'settled' && m.dropId === play.dropped.dropId)
    expect(plays.map((p) => p.dropped.nonce)).toEqual([0, 1, 2])

    // While the seed is active the player sees only its hash, everywhere.
    const beforeReveal = [
      JSON.stringify(await server.api('GET', '/api/me', { token })),
      JSON.stringify(await server.api('GET', '/api/seeds', { token })),
      JSON.stringify(await server.api('GET', '/api/drops', { token })),
      JSON.stringify(client.messages)
    ]
    const seeds = await server.api('GET', '/api/seeds', { token })
    expect(seeds.body.active).toMatchObject({ serverSeedHash: commitment, nonce: 3 })
    expect(seeds.body.revealed).toEqual([])

    const rotated = await server.api('POST', '/api/seeds/rotate', { token })
    expect(rotated.status).toBe(200)
    const { previousServerSeed, previousServerSeedHash, serverSeedHash, nonce, previousNonce } = rotated.body
    expect(previousServerSeedHash).toBe(commitment)
    expect(sha256(previousServerSeed)).toBe(commitment)
    expect(previousNonce).toBe(3)
    expect(nonce).toBe(0)
    expect(serverSeedHash).not.toBe(commitment)
    for (const text of beforeReveal) expect(text).not.toContain(previousServerSeed)

    // The revealed seed derives each drop seed (HMAC) and the engine replays each outcome.
    const { body: history } = await server.api('GET', '/api/drops', { token })
    expect(history.drops).toHaveLength(3)
    for (const { dropped, settled } of plays) {
      expect(hmac(previousServerSeed, `${dropped.clientSeed}:${dropped.nonce}`)).toBe(dropped.dropSeed)
      const verified = await verifyDrop({ serverSeed: previousServerSeed, clientSeed: dropped.clientSeed, nonce: dropped.nonce, rows: 14, risk: 'low' })
      expect(verified).toMatchObject({ serverSeedHash: commitment, dropSeed: dropped.dropSeed, bucket: settled.bucket, ticks: settled.ticks, stateHash: settled.stateHash })
      const stored = history.drops.find((d) => d.id === dropped.dropId)
      expect(stored).toMatchObject({ serverSeed: previousServerSeed, dropSeed: dropped.dropSeed, bucket: settled.bucket })
    }
    const afterSeeds = await server.api('GET', '/api/seeds', { token })
    expect(afterSeeds.body.revealed).toEqual([expect.objectContaining({ serverSeed: previousServerSeed, serverSeedHash: commitment, nonces: 3 })])
    expect(afterSeeds.body.active).toMatchObject({ serverSeedHash, nonce: 0 })

    // The next drop starts the new seed at nonce 0.
    const next = await dropAndSettle(client, { bet: 1 })
    expect(next.dropped).toMatchObject({ serverSeedHash, nonce: 0 })
    const [row] = await backend.query(database.database, 'SELECT COUNT(*) AS n FROM server_seeds WHERE player_id = $1 AND active = 1', [session.playerId])
    expect(Number(row.n)).toBe(1)
    await client.close()
  })

  it('rotates safely while a ball is in flight: the drop keeps its seed and still settles', async () => {
    const { session, client, token } = await server.player('13-high')
    client.send({ type: 'drop', bet: 9 })
    const dropped = await client.take('dropped')
    const rotated = await server.api('POST', '/api/seeds/rotate', { token })
    expect(rotated.body).toMatchObject({ previousServerSeedHash: session.serverSeedHash, previousNonce: 1 })
    expect(hmac(rotated.body.previousServerSeed, `${dropped.clientSeed}:0`)).toBe(dropped.dropSeed)
    const settled = await client.take('settled')
    expect(settled.dropId).toBe(dropped.dropId)
    const [row] = await backend.query(database.database, 'SELECT status, server_seed_hash FROM drops WHERE id = $1', [dropped.dropId])
    expect(row).toEqual({ status: 'settled', server_seed_hash: session.serverSeedHash })
    client.send({ type: 'drop', bet: 9 })
    expect(await client.take('dropped')).toMatchObject({ serverSeedHash: rotated.body.serverSeedHash, nonce: 0 })
    await client.close()
  })

  it('uses the client seed set over HTTP or with a drop, and never reuses a nonce', async () => {
    const { client, token, session } = await server.player('14-medium')
    const put = await server.api('PUT', '/api/seeds/client', { token, body: { clientSeed: 'lucky seven' } })
    expect(put.status).toBe(200)
    expect(put.body).toEqual({ clientSeed: 'lucky seven', serverSeedHash: session.serverSeedHash, nonce: 0 })
    const first = await dropAndSettle(client, { bet: 2 })
    expect(first.dropped).toMatchObject({ clientSeed: 'lucky seven', nonce: 0 })

    const second = await dropAndSettle(client, { bet: 2, clientSeed: 'my own: seed!' })
    expect(second.dropped).toMatchObject({ clientSeed: 'my own: seed!', nonce: 1 })
    expect((await server.api('GET', '/api/me', { token })).body.clientSeed).toBe('my own: seed!')

    const rows = await backend.query(database.database, 'SELECT client_seed, nonce FROM drops WHERE player_id = $1 ORDER BY id', [session.playerId])
    expect(rows.map((r) => [r.client_seed, Number(r.nonce)])).toEqual([['lucky seven', 0], ['my own: seed!', 1]])
    const [player] = await backend.query(database.database, 'SELECT client_seed FROM players WHERE id = $1', [session.playerId])
    expect(player.client_seed).toBe('my own: seed!')
    await client.close()
  })

  it('lets a player read only their own drops', async () => {
    const alice = await server.player('15-high')
    const bob = await server.player()
    const { dropped } = await dropAndSettle(alice.client, { bet: 4 })
    expect((await server.api('GET', `/api/drops/${dropped.dropId}`, { token: alice.token })).body).toMatchObject({ id: dropped.dropId, playerId: alice.session.playerId })
    // Someone else's drop answers exactly as no drop does: ids cannot be counted.
    const someoneElses = await server.api('GET', `/api/drops/${dropped.dropId}`, { token: bob.token })
    const none = await server.api('GET', `/api/drops/${dropped.dropId + 1000}`, { token: bob.token })
    expect(someoneElses.status).toBe(404)
    expect(someoneElses.body).toEqual({ ...none.body, message: none.body.message.replace(String(dropped.dropId + 1000), String(dropped.dropId)) })
    const bobsList = await server.api('GET', '/api/drops?limit=500', { token: bob.token })
    expect(bobsList.body.drops).toEqual([])
    // A page's cursor is one of the caller's drops; another's is not found, as an id that is no drop is.
    expect((await server.api('GET', `/api/drops?before=${dropped.dropId}`, { token: alice.token })).body).toEqual({ drops: [] })
    const pastSomeoneElses = await server.api('GET', `/api/drops?before=${dropped.dropId}`, { token: bob.token })
    const pastNone = await server.api('GET', `/api/drops?before=${dropped.dropId + 1000}`, { token: bob.token })
    expect(pastSomeoneElses.status).toBe(404)
    expect(pastSomeoneElses.body).toMatchObject({ code: 'E_NOT_FOUND', message: expect.stringMatching(/previous page's last drop/) })
    expect(pastSomeoneElses.body).toEqual({ ...pastNone.body, message: pastNone.body.message.replace(String(dropped.dropId + 1000), String(dropped.dropId)) })
    await alice.client.close()
  })
})
