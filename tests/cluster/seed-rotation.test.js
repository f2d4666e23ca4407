import { describe, it, expect } from 'vitest'
import Redis from 'ioredis'
import { clusterTestbed, query, ledgerMismatches, eventually } from './helpers/cluster.js'

/**
 * A rotation on one worker while the player keeps a tab open on another
 * (real PostgreSQL and Redis, two server processes). The other worker
 * holds the player's account in memory for as long as that tab is open; it
 * used to keep the revealed seed: every drop there got E_SEED_ROTATED
 * (reconnecting did not help, the account stayed), and its `welcome` and
 * /api/me showed the revealed hash as the active commitment. The rotation
 * now reaches every worker through Redis before it is answered.
 */
const ROTATIONS = 5

describe('cluster: a seed rotation reaches every worker', () => {
  const testbed = clusterTestbed()
  const { connect, join } = testbed

  it('switches the other worker to the new seed before the rotation is answered', async () => {
    const databaseUrl = await testbed.postgres.createDatabase()
    const a = await testbed.startNode({ databaseUrl })
    const b = await testbed.startNode({ databaseUrl })
    const player = await a.session()
    const auth = { authorization: `Bearer ${player.token}` }
    const onA = await connect(a, player.token)
    const idleOnB = await connect(b, player.token)
    expect(await join(onA, '10-low')).toMatchObject({ type: 'joined' })
    expect(await join(idleOnB, '9-low')).toMatchObject({ type: 'joined' })

    for (let i = 0; i < ROTATIONS; i++) {
      const response = await fetch(`${a.url}/api/seeds/rotate`, { method: 'POST', headers: auth })
      expect(response.status).toBe(200)
      const rotated = await response.json()
      // At once, on the other worker: the next drop uses the new seed.
      idleOnB.send({ type: 'drop', bet: 1, ref: `b${i}` })
      const reply = await idleOnB.take((m) => m.ref === `b${i}`)
      expect(reply, `drop on the other worker after rotation ${i + 1}`).toMatchObject({ type: 'dropped', serverSeedHash: rotated.serverSeedHash })
      // Its commitment on display is the new one.
      const me = await (await fetch(`${b.url}/api/me`, { headers: auth })).json()
      expect(me.serverSeedHash).toBe(rotated.serverSeedHash)
      const fresh = await connect(b, player.token)
      expect(fresh.welcome.serverSeedHash).toBe(rotated.serverSeedHash)
      await fresh.close()
      onA.send({ type: 'drop', bet: 1, ref: `a${i}` })
      expect(await onA.take((m) => m.ref === `a${i}`)).toMatchObject({ type: 'dropped', serverSeedHash: rotated.serverSeedHash })
    }

    await eventually(async () => Number((await query(databaseUrl, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'"))[0].n) === 0)
    const late = await query(databaseUrl, `SELECT d.id FROM drops d JOIN server_seeds s ON s.id = d.server_seed_id
      WHERE s.revealed_at IS NOT NULL AND d.created_at > s.revealed_at`)
    expect(late).toEqual([])
    const [{ n }] = await query(databaseUrl, 'SELECT COUNT(*) AS n FROM drops WHERE player_id = $1', [player.playerId])
    expect(Number(n)).toBe(2 * ROTATIONS)
    expect(await ledgerMismatches(databaseUrl, 100000)).toEqual([])
    console.info(`[cluster seed rotation] ${ROTATIONS} rotations on one worker: the next drop on the other worker used the new seed every time; its welcome and /api/me showed the new commitment`)
  })
  it('a worker that missed the notice switches on its first refused drop instead of locking the player out', async () => {
    const databaseUrl = await testbed.postgres.createDatabase()
    const a = await testbed.startNode({ databaseUrl })
    const b = await testbed.startNode({ databaseUrl })
    const player = await a.session()
    const onB = await connect(b, player.token)
    expect(await join(onB, '9-medium')).toMatchObject({ type: 'joined' })
    // Every subscriber is cut off (they reconnect within ~50 ms): the rotation's notice reaches no one.
    const admin = new Redis(testbed.redis.url)
    await admin.client('KILL', 'TYPE', 'pubsub')
    const response = await fetch(`${a.url}/api/seeds/rotate`, { method: 'POST', headers: { authorization: `Bearer ${player.token}` } })
    await admin.quit()
    expect(response.status).toBe(200)
    const rotated = await response.json()
    onB.send({ type: 'drop', bet: 1, ref: 'first' })
    const first = await onB.take((m) => m.ref === 'first')
    if (first.type === 'error') expect(first.code).toBe('E_SEED_ROTATED')
    else expect(first.serverSeedHash).toBe(rotated.serverSeedHash)
    onB.send({ type: 'drop', bet: 1, ref: 'second' })
    expect(await onB.take((m) => m.ref === 'second')).toMatchObject({ type: 'dropped', serverSeedHash: rotated.serverSeedHash })
    console.info(`[cluster seed rotation] notice lost: the first drop on the other worker ${first.type === 'error' ? 'was refused (E_SEED_ROTATED)' : 'went through (the notice came anyway)'}, the second used the new seed`)
    await eventually(async () => Number((await query(databaseUrl, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'"))[0].n) === 0)
    expect(await ledgerMismatches(databaseUrl, 100000)).toEqual([])
  })
})
