import { describe, it, expect } from 'vitest'
import Redis from 'ioredis'
import { clusterTestbed, query, ledgerMismatches, roomTotalMismatches, eventually } from './helpers/cluster.js'

/**
 * A process loses a room's lease with drops in flight, and drops still
 * arriving (issue #13's bug): another process takes the room over. Every
 * drop is settled exactly once, and on the process that lost the room the
 * player can bet its whole balance again.
 */
const LEASE_TTL_MS = 1500
const START = 100000

describe('cluster: a lease lost with drops in flight', () => {
  const testbed = clusterTestbed()
  const { connect, join } = testbed

  it('settles every drop exactly once and leaves the whole balance available on the process that lost the room', async () => {
    const databaseUrl = await testbed.postgres.createDatabase()
    const env = { LEASE_TTL_MS: String(LEASE_TTL_MS), DROP_RATE: '200', DROP_BURST: '200' }
    const [a, b] = [await testbed.startNode({ databaseUrl, env }), await testbed.startNode({ databaseUrl, env })]
    const alice = await a.session()
    const onA = await connect(a, alice.token)
    expect(await join(onA, '16-high')).toMatchObject({ type: 'joined' })
    // Balls in flight on A, and more arriving every 10 ms while the room moves.
    for (let i = 0; i < 10; i++) onA.send({ type: 'drop', bet: 7 })
    for (let i = 0; i < 10; i++) await onA.take('dropped')
    let sending = true
    const sender = (async () => {
      while (sending && onA.socket.readyState === 1) {
        onA.send({ type: 'drop', bet: 3 })
        await new Promise((resolve) => setTimeout(resolve, 10))
      }
    })()
    // The lease goes to B: A's expires and B takes it (here: the lease is handed to B's id at
    // once; deleting it instead left a window in which A's renewal took an unowned lease back
    // before B's join came), then a player joins the room on B.
    const redisClient = new Redis(testbed.redis.url)
    try {
      const nodeIdOf = async (node) => {
        for (const key of await redisClient.keys('plinko:node:*')) {
          if (await redisClient.get(key) === node.url) return key.slice('plinko:node:'.length)
        }
        return null
      }
      const idOfB = await eventually(() => nodeIdOf(b))
      await redisClient.set('plinko:room:16-high:lease', idOfB, 'PX', LEASE_TTL_MS)
      const bob = await b.session()
      const onB = await connect(b, bob.token)
      expect(await join(onB, '16-high')).toMatchObject({ type: 'joined' })
    } finally {
      redisClient.disconnect()
    }
    const moved = await onA.take((m) => m.type === 'error' && m.code === 'E_ROOM_MOVING', LEASE_TTL_MS * 3)
    expect(moved.room).toBe('16-high')
    await new Promise((resolve) => setTimeout(resolve, 200))
    sending = false
    await sender

    // Every drop recorded is settled, once; balances add up.
    const inFlight = async () => query(databaseUrl, "SELECT id FROM drops WHERE status = 'in_flight'")
    await eventually(async () => (await inFlight()).length === 0, { timeoutMs: 20_000 })
      .catch(async (error) => { throw new Error(`drops left in flight: ${JSON.stringify(await inFlight())} (${error.message})`) })
    const rows = await query(databaseUrl, 'SELECT id, bet, payout, status FROM drops WHERE player_id = $1 ORDER BY id', [alice.playerId])
    expect(rows.length).toBeGreaterThan(10)
    expect(new Set(rows.map((r) => r.id)).size).toBe(rows.length)
    expect(await ledgerMismatches(databaseUrl, START)).toEqual([])
    // The lost room's settlements, refused or made by either process, each counted once in its room's totals.
    expect(await roomTotalMismatches(databaseUrl)).toEqual([])
    const [{ balance }] = await query(databaseUrl, 'SELECT balance FROM players WHERE id = $1', [alice.playerId])

    // On A, the whole committed balance can be bet again (nothing stays reserved by the lost room's drops).
    await eventually(async () => {
      const again = await connect(a, alice.token)
      return again.welcome.balance === Number(balance) / 1000 // the ledger holds milli-credits
    }, { timeoutMs: 10_000 })
    const onA2 = await connect(a, alice.token)
    expect(await join(onA2, '8-low')).toMatchObject({ type: 'joined' })
    const allIn = Math.floor(Number(balance) / 1000) // every whole credit of it
    onA2.send({ type: 'drop', bet: allIn, ref: 'all-in' })
    const reply = await onA2.take((m) => m.ref === 'all-in')
    expect(reply, JSON.stringify(reply)).toMatchObject({ type: 'dropped', bet: allIn })
  }, 120_000)
})
