/**
 * An upgrade from engine 1.0.0: the ledger a real 1.0.0 server left behind
 * (tests/fixtures/ledger-1.0.0: 24 settled drops, 6 killed in flight with
 * SIGKILL, one player's seed rotated and revealed) is opened by this server,
 * which decides new drops under the newest version. Every old drop must
 * still verify under the version it was decided under, and the drops in
 * flight across the upgrade settle under 1.0.0.
 */
import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { createBoard, simulateDrop, verifyDrop, ENGINE_VERSION } from '../../engine/index.js'
import { payoutFor } from '../../server/game/money.js'
import { STORE_KINDS, storeBackend, roomSumsOverDrops } from './helpers/stores.js'
import { startServer, OPERATOR_TOKEN } from './helpers/server.js'
import { ledgerFixture, loadLedgerFixture, fixtureDrops, fixturePlayers } from '../helpers/ledger-fixture.js'
import { MIGRATIONS } from '../../server/store/migrations.js'

const OLD = '1.0.0'
const fixture = ledgerFixture(OLD)
const recordedBefore = fixtureDrops(fixture)
const operator = { token: OPERATOR_TOKEN }
const simulate = (drop, engineVersion) => simulateDrop(createBoard({ rows: drop.rows, risk: drop.risk, engineVersion }), drop.drop_seed ?? drop.dropSeed)

describe.each(STORE_KINDS)('engine upgrade from 1.0.0 on %s', (kind) => {
  const backend = storeBackend(kind)
  let database
  let server

  beforeAll(async () => {
    expect(ENGINE_VERSION).not.toBe(OLD)
    expect(fixture.engineVersion).toBe(OLD)
    await backend.setup()
    database = await backend.newDatabase()
    await loadLedgerFixture(database, fixture)
    server = await startServer(database)
  })
  afterAll(async () => {
    await server?.close()
    await backend.teardown()
  })

  it('settles the drops left in flight by the 1.0.0 server under 1.0.0, at start-up', async () => {
    expect(recordedBefore.filter((d) => d.status === 'in_flight').map((d) => d.id)).toEqual(fixture.inFlightDropIds)
    const rows = await backend.query(database.database, `SELECT * FROM drops WHERE id IN (${fixture.inFlightDropIds.join(', ')}) ORDER BY id`)
    expect(rows).toHaveLength(fixture.inFlightDropIds.length)
    let differsUnderNewest = 0
    for (const row of rows) {
      expect(row.status).toBe('settled')
      expect(row.engine_version).toBe(OLD)
      const old = simulate(row, OLD)
      // Recorded before migration 2: paid under the legacy rule (whole credits), held in milli-credits.
      expect({ bucket: row.bucket, ticks: row.ticks, state_hash: row.state_hash, payout: Number(row.payout), payout_rule: Number(row.payout_rule) })
        .toEqual({ bucket: old.bucket, ticks: old.ticks, state_hash: old.stateHash, payout: payoutFor(Number(row.bet), old.multiplier, 1), payout_rule: 1 })
      expect(Number(row.payout) % 1000).toBe(0)
      if (simulate(row, ENGINE_VERSION).stateHash !== old.stateHash) differsUnderNewest++
    }
    // The version matters: the newest engine would have decided these drops differently.
    expect(differsUnderNewest).toBe(rows.length)
  })

  it('keeps what players were told before the upgrade: every settled drop as announced', async () => {
    for (const settled of fixture.settled) {
      const [row] = await backend.query(database.database, 'SELECT * FROM drops WHERE id = $1', [settled.dropId])
      expect({ bucket: row.bucket, payout: Number(row.payout), payoutRule: Number(row.payout_rule), ticks: row.ticks, stateHash: row.state_hash, engineVersion: row.engine_version })
        .toEqual({ bucket: settled.bucket, payout: settled.payout * 1000, payoutRule: 1, ticks: settled.ticks, stateHash: settled.stateHash, engineVersion: OLD })
    }
  })

  it('moves every balance to milli-credits exactly once (migration 2), the drops it settled credited on top', async () => {
    const source = fixturePlayers(fixture)
    for (const player of source) {
      const [row] = await backend.query(database.database, 'SELECT balance FROM players WHERE id = $1', [player.id])
      const credited = (await backend.query(database.database, `SELECT payout FROM drops WHERE player_id = $1 AND id IN (${fixture.inFlightDropIds.join(', ')})`, [player.id]))
        .reduce((sum, d) => sum + Number(d.payout), 0)
      expect(Number(row.balance)).toBe(player.balance * 1000 + credited)
    }
    const [{ version }] = await backend.query(database.database, 'SELECT MAX(version) AS version FROM schema_migrations')
    expect(Number(version)).toBe(MIGRATIONS.at(-1).version)
  })

  it('audits every 1.0.0 drop under 1.0.0 (GET /api/audit/drops/:id)', async () => {
    for (const { id } of recordedBefore) {
      const { status, body } = await server.api('GET', `/api/audit/drops/${id}`, operator)
      expect(status).toBe(200)
      expect(body.drop.engineVersion).toBe(OLD)
      expect(body.replay.engineVersion).toBe(OLD)
      expect(body.matches, `drop ${id}: ${JSON.stringify(body.checks)}`).toBe(true)
    }
  })

  it('verifies revealed 1.0.0 seeds under 1.0.0 and tells the versions apart (GET /api/audit/verify)', async () => {
    const a = fixture.players.a
    const revealed = recordedBefore.filter((d) => d.server_seed_hash === a.revealedServerSeedHash)
    expect(revealed.length).toBeGreaterThan(10)
    for (const drop of revealed) {
      const query = `serverSeed=${a.revealedServerSeed}&clientSeed=${encodeURIComponent(drop.client_seed)}&nonce=${drop.nonce}&rows=${drop.rows}&risk=${drop.risk}`
      const old = await server.api('GET', `/api/audit/verify?${query}&engineVersion=${OLD}`, operator)
      expect(old.status).toBe(200)
      expect(old.body).toMatchObject({ engineVersion: OLD, dropSeed: drop.drop_seed, bucket: drop.bucket, ticks: drop.ticks, stateHash: drop.state_hash })
      expect(old.body.recorded).toEqual([{ id: drop.id, matches: true }])
      // The same seeds under the newest version: another outcome, and the recorded drop does not match it.
      const newest = await server.api('GET', `/api/audit/verify?${query}`, operator)
      expect(newest.body.engineVersion).toBe(ENGINE_VERSION)
      expect(newest.body.stateHash).not.toBe(drop.state_hash)
      expect(newest.body.recorded).toEqual([{ id: drop.id, matches: false }])
    }
    const unknown = await server.api('GET', `/api/audit/verify?serverSeed=x&clientSeed=y&nonce=0&engineVersion=0.9.9`, operator)
    expect(unknown.status).toBe(400)
    expect(unknown.body.code).toBe('E_UNKNOWN_ENGINE_VERSION')
    expect(unknown.body.message).toContain(OLD)
  })

  it('shows players their 1.0.0 drops with the version, and they verify under it', async () => {
    const a = fixture.players.a
    const { status, body } = await server.api('GET', '/api/drops?limit=100', { token: a.token })
    expect(status).toBe(200)
    const own = recordedBefore.filter((d) => d.player_id === a.playerId)
    expect(body.drops).toHaveLength(own.length)
    const revealed = body.drops.filter((d) => d.serverSeed !== null)
    expect(revealed.length).toBeGreaterThan(10)
    for (const drop of revealed) {
      expect(drop.engineVersion).toBe(OLD)
      const verified = await verifyDrop({ ...drop, engineVersion: drop.engineVersion })
      expect({ serverSeedHash: verified.serverSeedHash, dropSeed: verified.dropSeed, bucket: verified.bucket, ticks: verified.ticks, stateHash: verified.stateHash })
        .toEqual({ serverSeedHash: drop.serverSeedHash, dropSeed: drop.dropSeed, bucket: drop.bucket, ticks: drop.ticks, stateHash: drop.stateHash })
    }
  })

  it('decides new drops under the newest version, announces it, and audits them under it', async () => {
    const { client } = await server.player('16-high')
    expect(client.welcome.engineVersion).toBe(ENGINE_VERSION)
    expect(client.joined.engineVersion).toBe(ENGINE_VERSION)
    client.send({ type: 'drop', bet: 10, ref: 'new' })
    const dropped = await client.take('dropped')
    expect(dropped.engineVersion).toBe(ENGINE_VERSION)
    const settled = await client.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    const replay = simulateDrop(createBoard({ rows: 16, risk: 'high' }), dropped.dropSeed)
    expect({ bucket: settled.bucket, stateHash: settled.stateHash }).toEqual({ bucket: replay.bucket, stateHash: replay.stateHash })
    const audit = await server.api('GET', `/api/audit/drops/${dropped.dropId}`, operator)
    expect(audit.body.drop.engineVersion).toBe(ENGINE_VERSION)
    expect(audit.body.matches).toBe(true)
  })

  it('keeps room statistics per engine version', async () => {
    const old = await server.api('GET', `/api/audit/rooms/16-high/stats?engineVersion=${OLD}`, operator)
    expect(old.status).toBe(200)
    expect(old.body.engineVersion).toBe(OLD)
    expect(old.body.settled).toBe(recordedBefore.filter((d) => d.room === '16-high').length)
    expect(old.body.multipliers).toEqual(createBoard({ rows: 16, risk: 'high', engineVersion: OLD }).multipliers)
    const newest = await server.api('GET', '/api/audit/rooms/16-high/stats', operator)
    expect(newest.body.engineVersion).toBe(ENGINE_VERSION)
    expect(newest.body.multipliers).toEqual(createBoard({ rows: 16, risk: 'high' }).multipliers)
    // The 1.0.0 rooms' totals by bucket (migration 3 summed the drops settled before it, the start-up added the rest): the sums over their drops.
    for (const room of new Set(recordedBefore.map((d) => d.room))) {
      const { body } = await server.api('GET', `/api/audit/rooms/${room}/stats?engineVersion=${OLD}`, operator)
      const sums = await roomSumsOverDrops(backend, database.database, room, OLD)
      expect(sums.buckets.length).toBeGreaterThan(0)
      expect(body.buckets).toEqual(sums.buckets)
      expect(body.inFlight).toBe(0)
    }
    const bad = await server.api('GET', '/api/audit/rooms/16-high/stats?engineVersion=nope', operator)
    expect(bad.body.code).toBe('E_UNKNOWN_ENGINE_VERSION')
  })
})
