import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { STORE_KINDS, storeBackend } from './helpers/stores.js'
import { startServer, OPERATOR_TOKEN } from './helpers/server.js'

const AUDIT_URLS = [
  '/api/audit/drops/1',
  '/api/audit/drops?limit=5',
  '/api/audit/verify?serverSeed=a&clientSeed=b&nonce=0',
  '/api/audit/export?player=x',
  '/api/audit/rooms/16-medium/stats'
]

describe.each(STORE_KINDS)('operator audit API on %s', (kind) => {
  const backend = storeBackend(kind)
  let server
  let database
  let alice
  let bob
  let aliceDrops
  let bobDrop

  beforeAll(async () => {
    await backend.setup()
    database = await backend.newDatabase()
    server = await startServer(database)
    alice = await server.player('16-medium')
    bob = await server.player('16-medium')
    for (const bet of [10, 20, 30]) alice.client.send({ type: 'drop', bet })
    bob.client.send({ type: 'drop', bet: 40 })
    aliceDrops = []
    for (let i = 0; i < 3; i++) aliceDrops.push(await alice.client.take((m) => m.type === 'settled' && m.player === alice.session.playerId))
    bobDrop = await bob.client.take((m) => m.type === 'settled' && m.player === bob.session.playerId)
  })

  afterAll(async () => {
    await server?.close()
    await backend.teardown()
  })

  it('refuses every audit endpoint without a token, with a wrong one, and with a player token', async () => {
    for (const url of AUDIT_URLS) {
      const none = await server.api('GET', url)
      expect(none.status, url).toBe(401)
      expect(none.body.code).toBe('E_UNAUTHORIZED')
      const wrong = await server.api('GET', url, { token: OPERATOR_TOKEN.slice(0, -1) + 'X' })
      expect(wrong.status, url).toBe(403)
      expect(wrong.body.code).toBe('E_FORBIDDEN')
      const player = await server.api('GET', url, { token: alice.token })
      expect(player.status, url).toBe(403)
      const shortToken = await server.api('GET', url, { token: 'x' })
      expect(shortToken.status, url).toBe(403)
    }
  })

  it('returns a drop with a fresh re-simulation that matches, and notices tampering', async () => {
    const settled = aliceDrops[0]
    const response = await server.api('GET', `/api/audit/drops/${settled.dropId}`, { token: OPERATOR_TOKEN })
    expect(response.status).toBe(200)
    const { drop, replay, checks, matches } = response.body
    expect(matches).toBe(true)
    expect(Object.values(checks).every((check) => check === true)).toBe(true)
    expect(drop).toMatchObject({ id: settled.dropId, playerId: alice.session.playerId, bucket: settled.bucket, payout: settled.payout, status: 'settled', serverSeed: null })
    expect(replay).toMatchObject({ bucket: settled.bucket, ticks: settled.ticks, stateHash: settled.stateHash, payout: settled.payout, dropSeed: drop.dropSeed, serverSeedHash: drop.serverSeedHash })
    // The active seed is used for the HMAC check but never returned.
    const seedRows = await backend.query(database.database, 'SELECT seed FROM server_seeds WHERE player_id = $1', [alice.session.playerId])
    expect(response.text).not.toContain(seedRows[0].seed)

    const tampered = aliceDrops[1]
    await backend.query(database.database, 'UPDATE drops SET bucket = $1 WHERE id = $2', [(tampered.bucket + 1) % 17, tampered.dropId])
    const after = await server.api('GET', `/api/audit/drops/${tampered.dropId}`, { token: OPERATOR_TOKEN })
    expect(after.body.matches).toBe(false)
    expect(after.body.checks).toMatchObject({ bucket: false, dropSeed: true, serverSeedHash: true, ticks: true })
    await backend.query(database.database, 'UPDATE drops SET bucket = $1 WHERE id = $2', [tampered.bucket, tampered.dropId])

    const forgedSeed = aliceDrops[2]
    const [original] = await backend.query(database.database, 'SELECT drop_seed FROM drops WHERE id = $1', [forgedSeed.dropId])
    await backend.query(database.database, "UPDATE drops SET drop_seed = 'forged' WHERE id = $1", [forgedSeed.dropId])
    const forged = await server.api('GET', `/api/audit/drops/${forgedSeed.dropId}`, { token: OPERATOR_TOKEN })
    expect(forged.body.matches).toBe(false)
    expect(forged.body.checks.dropSeed).toBe(false)
    await backend.query(database.database, 'UPDATE drops SET drop_seed = $1 WHERE id = $2', [original.drop_seed, forgedSeed.dropId])
    expect((await server.api('GET', `/api/audit/drops/${forgedSeed.dropId}`, { token: OPERATOR_TOKEN })).body.matches).toBe(true)

    expect((await server.api('GET', '/api/audit/drops/999999', { token: OPERATOR_TOKEN })).status).toBe(404)
  })

  it('lists drops by player and time, and verifies seeds against the ledger', async () => {
    const byAlice = await server.api('GET', `/api/audit/drops?player=${alice.session.playerId}`, { token: OPERATOR_TOKEN })
    expect(byAlice.body.drops.map((d) => d.id)).toEqual(aliceDrops.map((d) => d.dropId).sort((a, b) => b - a))
    const [first] = byAlice.body.drops.slice(-1)
    const from = Date.parse(first.createdAt)
    const window = await server.api('GET', `/api/audit/drops?from=${from}&to=${new Date(from + 1).toISOString()}`, { token: OPERATOR_TOKEN })
    expect(window.body.drops.map((d) => d.id)).toContain(first.id)
    for (const d of window.body.drops) expect(Date.parse(d.createdAt)).toBe(from)
    const future = await server.api('GET', `/api/audit/drops?from=${Date.now() + 60_000}`, { token: OPERATOR_TOKEN })
    expect(future.body.drops).toEqual([])

    // After Bob rotates, the verifier recomputes his drop and finds it in the ledger.
    const rotated = await server.api('POST', '/api/seeds/rotate', { token: bob.token })
    const [bobRecord] = (await server.api('GET', '/api/drops', { token: bob.token })).body.drops
    const query = new URLSearchParams({ serverSeed: rotated.body.previousServerSeed, clientSeed: bobRecord.clientSeed, nonce: '0', rows: '16', risk: 'medium' })
    const verified = await server.api('GET', `/api/audit/verify?${query}`, { token: OPERATOR_TOKEN })
    expect(verified.status).toBe(200)
    expect(verified.body).toMatchObject({ serverSeedHash: bob.session.serverSeedHash, dropSeed: bobRecord.dropSeed, bucket: bobDrop.bucket, ticks: bobDrop.ticks, stateHash: bobDrop.stateHash })
    expect(verified.body.recorded).toEqual([{ id: bobDrop.dropId, matches: true }])
    const otherBoard = await server.api('GET', `/api/audit/verify?${query.toString().replace('risk=medium', 'risk=high')}`, { token: OPERATOR_TOKEN })
    expect(otherBoard.body.recorded).toEqual([{ id: bobDrop.dropId, matches: false }])
  })

  it('exports a player\'s or a seed\'s whole history as JSON and JSON lines', async () => {
    const json = await server.api('GET', `/api/audit/export?player=${alice.session.playerId}`, { token: OPERATOR_TOKEN })
    expect(json.status).toBe(200)
    expect(json.headers['content-type']).toMatch(/^application\/json/)
    const array = JSON.parse(json.text)
    expect(array.map((d) => d.id)).toEqual(aliceDrops.map((d) => d.dropId).sort((a, b) => a - b))
    expect(array.every((d) => d.playerId === alice.session.playerId && d.status === 'settled')).toBe(true)

    const lines = await server.api('GET', `/api/audit/export?serverSeedHash=${bob.session.serverSeedHash}&format=ndjson`, { token: OPERATOR_TOKEN })
    expect(lines.headers['content-type']).toMatch(/^application\/x-ndjson/)
    const records = lines.text.trim().split('\n').map((line) => JSON.parse(line))
    expect(records).toHaveLength(1)
    expect(records[0]).toMatchObject({ id: bobDrop.dropId, serverSeedHash: bob.session.serverSeedHash })
    const both = await server.api('GET', `/api/audit/export?player=a&serverSeedHash=${bob.session.serverSeedHash}`, { token: OPERATOR_TOKEN })
    expect(both.status).toBe(400)
  })

  it("refuses an export's query that breaks its schema (the fuzzer's negative check is off for it: scripts/fuzz-api.toml)", async () => {
    const hash = bob.session.serverSeedHash
    const refusals = [
      ['neither history', '/api/audit/export', /exactly one of player or serverSeedHash/],
      ['both histories', `/api/audit/export?player=a&serverSeedHash=${hash}`, /exactly one of player or serverSeedHash/],
      ['an unknown parameter', '/api/audit/export?player=a&extra=1', /must NOT have additional properties/],
      ['an empty player', '/api/audit/export?player=', /player/],
      ['a control character in the player', '/api/audit/export?player=a%0Ab', /player/],
      ['a player longer than 64', `/api/audit/export?player=${'a'.repeat(65)}`, /player/],
      ['a hash that is not 64 hex digits', `/api/audit/export?serverSeedHash=${hash.slice(1)}`, /serverSeedHash/],
      ['an unknown format', '/api/audit/export?player=a&format=csv', /format/]
    ]
    for (const [what, url, message] of refusals) {
      const response = await server.api('GET', url, { token: OPERATOR_TOKEN })
      expect(response.status, what).toBe(400)
      expect(response.body.code, what).toBe('E_BAD_REQUEST')
      expect(response.body.message, what).toMatch(message)
    }
    // A percent sign and other printable characters are a player id like any other: nothing of theirs, nothing exported.
    const printable = await server.api('GET', `/api/audit/export?player=${encodeURIComponent('Um+}/EWXA%0AJm`0lR')}`, { token: OPERATOR_TOKEN })
    expect(printable.status).toBe(200)
    expect(JSON.parse(printable.text)).toEqual([])
  })

  it('reports room statistics that agree with the ledger', async () => {
    const stats = await server.api('GET', '/api/audit/rooms/16-medium/stats', { token: OPERATOR_TOKEN })
    expect(stats.status).toBe(200)
    const [sums] = await backend.query(database.database,
      "SELECT COUNT(*) AS n, SUM(bet) AS bet, SUM(payout) AS payout FROM drops WHERE room = '16-medium' AND status = 'settled'")
    // The ledger holds payouts in milli-credits; the API shows credits.
    expect(stats.body).toMatchObject({ room: '16-medium', rows: 16, risk: 'medium', settled: Number(sums.n), totalBet: Number(sums.bet), totalPayout: Number(sums.payout) / 1000, inFlight: 0 })
    expect(stats.body.settled).toBe(4)
    expect(stats.body.rtp).toBeCloseTo(Number(sums.payout) / 1000 / Number(sums.bet), 12)
    expect(stats.body.bucketCounts).toHaveLength(17)
    expect(stats.body.bucketCounts.reduce((a, b) => a + b, 0)).toBe(4)
    for (const s of [...aliceDrops, bobDrop]) expect(stats.body.bucketCounts[s.bucket]).toBeGreaterThan(0)
    expect(stats.body.multipliers).toHaveLength(17)
    expect(stats.body.live).toMatchObject({ players: 2 })
    const empty = await server.api('GET', '/api/audit/rooms/8-low/stats', { token: OPERATOR_TOKEN })
    expect(empty.body).toMatchObject({ settled: 0, totalBet: 0, rtp: null, live: null })
  })
})
