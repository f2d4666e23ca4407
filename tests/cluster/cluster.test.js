import { describe, it, expect } from 'vitest'
import Redis from 'ioredis'
import { clusterTestbed, query, ledgerMismatches, eventually } from './helpers/cluster.js'

/**
 * The clustered topology without Docker: a real PostgreSQL, a real Redis
 * and two or three `node server/server.js` processes (REDIS_URL set).
 */
const LEASE_TTL_MS = 1500
const START = 100000

describe('cluster: rooms, redirects, shared balances and takeover', () => {
  const testbed = clusterTestbed()
  const { connect, join } = testbed

  async function cluster (count, env = {}) {
    const databaseUrl = await testbed.postgres.createDatabase()
    const started = []
    for (let i = 0; i < count; i++) started.push(await testbed.startNode({ databaseUrl, env: { LEASE_TTL_MS: String(LEASE_TTL_MS), ...env } }))
    return { databaseUrl, nodes: started }
  }


  it('lists rooms from any process and redirects a join to the owner', async () => {
    const { nodes: [a, b] } = await cluster(2)
    const alice = await a.session()
    const ca = await connect(a, alice.token)
    expect(await join(ca, '16-medium')).toMatchObject({ type: 'joined', room: '16-medium' })

    // B lists A's room, with A's URL.
    const listed = await eventually(async () => {
      const { body } = await b.api('GET', '/api/rooms')
      return body.rooms.find((room) => room.id === '16-medium' && room.players === 1)
    })
    expect(listed.owner).toBe(a.url)

    // A session made on B works anywhere; joining A's room on B is redirected.
    const bob = await b.session()
    const cb = await connect(b, bob.token)
    const moved = await join(cb, '16-medium')
    expect(moved).toMatchObject({ type: 'error', code: 'E_WRONG_NODE', room: '16-medium', owner: a.url })
    const again = await connect({ wsUrl: (token) => `${moved.owner.replace(/^http/, 'ws')}/ws?token=${token}` }, bob.token)
    expect(await join(again, '16-medium')).toMatchObject({ type: 'joined' })
    // B runs its own rooms.
    expect(await join(cb, '8-low')).toMatchObject({ type: 'joined', room: '8-low' })
    const fromA = await eventually(async () => (await a.api('GET', '/api/rooms')).body.rooms.find((room) => room.id === '8-low'))
    expect(fromA.owner).toBe(b.url)
  })

  it('never spends one balance twice across processes, keeps both processes\' view of it current, and never reuses a nonce', async () => {
    const { databaseUrl, nodes: [a, b] } = await cluster(2, { STARTING_BALANCE: '100' })
    const carol = await a.session()
    const onA = await connect(a, carol.token)
    const onB = await connect(b, carol.token)
    expect(await join(onA, '12-low')).toMatchObject({ type: 'joined' })
    expect(await join(onB, '13-low')).toMatchObject({ type: 'joined' })
    // Both processes believe the balance is 100: the database accepts one bet of 100.
    onA.send({ type: 'drop', bet: 100, ref: 'a' })
    onB.send({ type: 'drop', bet: 100, ref: 'b' })
    const replies = await Promise.all([
      onA.take((m) => m.ref === 'a'),
      onB.take((m) => m.ref === 'b')
    ])
    const accepted = replies.filter((m) => m.type === 'dropped')
    const refused = replies.filter((m) => m.type === 'error')
    expect(accepted).toHaveLength(1)
    expect(refused).toHaveLength(1)
    expect(refused[0].code).toBe('E_INSUFFICIENT_FUNDS')
    const [winner] = accepted
    const owner = winner.ref === 'a' ? onA : onB
    const settled = await owner.take((m) => m.type === 'settled' && m.dropId === winner.dropId)
    expect(settled.balance).toBe(100 - 100 + settled.payout)
    const rows = await query(databaseUrl, 'SELECT balance FROM players WHERE id = $1', [carol.playerId])
    expect(Number(rows[0].balance)).toBe(Math.round(settled.payout * 1000)) // the ledger holds milli-credits
    // The other process hears of it (Redis) and shows the committed balance on its connection too.
    const other = owner === onA ? onB : onA
    expect(await other.take((m) => m.type === 'balance' && m.balance === settled.payout)).toMatchObject({ balance: settled.payout })

    // Nonces across processes: both play small bets; every (seed, nonce) is distinct (UNIQUE holds) and all drops commit.
    const dave = await b.session()
    const d1 = await connect(a, dave.token)
    const d2 = await connect(b, dave.token)
    await join(d1, '12-low')
    await join(d2, '13-low')
    for (let i = 0; i < 10; i++) {
      d1.send({ type: 'drop', bet: 1, ref: `x${i}` })
      d2.send({ type: 'drop', bet: 1, ref: `y${i}` })
    }
    const dropped = []
    for (let i = 0; i < 10; i++) {
      dropped.push(await d1.take((m) => m.ref === `x${i}`))
      dropped.push(await d2.take((m) => m.ref === `y${i}`))
    }
    expect(dropped.every((m) => m.type === 'dropped')).toBe(true)
    expect(new Set(dropped.map((m) => m.nonce)).size).toBe(20)
    expect(new Set(dropped.map((m) => m.dropId)).size).toBe(20)
    await eventually(async () => Number((await query(databaseUrl, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'"))[0].n) === 0)
    expect(await ledgerMismatches(databaseUrl, 100)).toEqual([])
  })

  it('hands a room over at once when its owner shuts down gracefully (SIGTERM releases the leases)', async () => {
    const { databaseUrl, nodes: [a, b] } = await cluster(2)
    const erin = await a.session()
    const onA = await connect(a, erin.token)
    await join(onA, '15-low')
    onA.send({ type: 'drop', bet: 7, ref: 'g' })
    const dropped = await onA.take((m) => m.ref === 'g')
    expect(dropped.type).toBe('dropped')
    const stoppedAt = Date.now()
    expect((await a.stop()).code).toBe(0)
    const onB = await connect(b, erin.token)
    expect(await join(onB, '15-low')).toMatchObject({ type: 'joined' })
    const handoverMs = Date.now() - stoppedAt
    console.log(`graceful handover of 15-low took ${handoverMs} ms (shutdown included)`)
    expect(handoverMs).toBeLessThan(LEASE_TTL_MS)
    // The ball in flight was settled by A before it left.
    const [row] = await query(databaseUrl, 'SELECT status FROM drops WHERE id = $1', [dropped.dropId])
    expect(row.status).toBe('settled')
    expect(await ledgerMismatches(databaseUrl, START)).toEqual([])
  })

  it('stops running a room whose lease passed to another owner, and tells its players', async () => {
    const { nodes: [a] } = await cluster(1)
    const frank = await a.session()
    const onA = await connect(a, frank.token)
    await join(onA, '9-medium')
    const redisClient = new Redis(testbed.redis.url)
    try {
      await redisClient.set('plinko:room:9-medium:lease', 'another-process', 'PX', 60_000)
      const moved = await onA.take((m) => m.type === 'error' && m.code === 'E_ROOM_MOVING', LEASE_TTL_MS * 2)
      expect(moved.room).toBe('9-medium')
      expect(await onA.expectError({ type: 'drop', bet: 1 })).toMatchObject({ code: 'E_NOT_IN_ROOM' })
      expect((await join(onA, '9-medium')).code).toBe('E_ROOM_MOVING') // the other owner has no presence key
      await redisClient.del('plinko:room:9-medium:lease')
      expect(await join(onA, '9-medium')).toMatchObject({ type: 'joined' })
    } finally {
      redisClient.disconnect()
    }
  })

  it('takes over the rooms of a SIGKILLed process after the lease TTL and settles its drops exactly once', async () => {
    const { databaseUrl, nodes: [a, b, c] } = await cluster(3)
    // Players on A drop balls in two rooms; A dies with balls in flight.
    const players = []
    for (let i = 0; i < 4; i++) {
      const session = await a.session()
      const client = await connect(a, session.token)
      await join(client, i % 2 === 0 ? '16-high' : '14-medium')
      players.push({ session, client })
    }
    const dropped = []
    for (const { client } of players) for (let i = 0; i < 5; i++) client.send({ type: 'drop', bet: 10 + i, ref: `d${i}` })
    for (const { client } of players) for (let i = 0; i < 5; i++) dropped.push(await client.take((m) => m.ref === `d${i}` && m.type === 'dropped'))
    // Mid-load: more drops on the wire when A dies; some are recorded, some never are.
    for (const { client } of players) for (let i = 5; i < 8; i++) client.send({ type: 'drop', bet: 10 + i, ref: `d${i}` })
    await new Promise((resolve) => setTimeout(resolve, 20))
    await a.kill('SIGKILL')
    for (const { client } of players) dropped.push(...client.messages.filter((m) => m.type === 'dropped' && !dropped.includes(m)))
    const killedAt = Date.now()
    const inFlight = Number((await query(databaseUrl, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'"))[0].n)
    expect(inFlight).toBeGreaterThan(0)

    // A player moves to B and asks for 16-high: told to wait (A is gone) until the lease expires, then B runs it.
    const mover = players[0]
    const onB = await connect(b, mover.session.token)
    let joined
    const answers = []
    while (!joined) {
      const reply = await join(onB, '16-high')
      if (reply.type === 'joined') joined = reply
      else {
        answers.push(reply.code)
        await new Promise((resolve) => setTimeout(resolve, Math.min(200, reply.retryAfterMs ?? 100)))
      }
      expect(Date.now() - killedAt).toBeLessThan(LEASE_TTL_MS * 4)
    }
    const takeoverMs = Date.now() - killedAt
    expect(answers.every((code) => code === 'E_WRONG_NODE' || code === 'E_ROOM_MOVING')).toBe(true)
    console.log(`room 16-high ran again on another process ${takeoverMs} ms after SIGKILL (lease TTL ${LEASE_TTL_MS} ms)`)

    // 14-medium is rejoined by nobody: the sweep of B or C settles its drops.
    await eventually(async () => Number((await query(databaseUrl, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'"))[0].n) === 0, { timeoutMs: LEASE_TTL_MS * 6 })
    const rows = await query(databaseUrl, 'SELECT id, status, payout FROM drops ORDER BY id')
    // Every announced drop is recorded (a recorded drop may have died unannounced: it is still settled).
    const recorded = new Set(rows.map((r) => Number(r.id)))
    expect(dropped.filter((d) => !recorded.has(d.dropId))).toEqual([])
    console.log(`${rows.length} drops recorded (${new Set(dropped.map((d) => d.dropId)).size} announced before SIGKILL), ${inFlight} were in flight`)
    expect(rows.every((r) => r.status === 'settled')).toBe(true)
    expect(await ledgerMismatches(databaseUrl, START)).toEqual([])

    // The mover's balance on B is the ledger's, and play goes on there.
    const [me] = await query(databaseUrl, 'SELECT balance FROM players WHERE id = $1', [mover.session.playerId])
    onB.send({ type: 'drop', bet: 1, ref: 'after' })
    const next = await onB.take((m) => m.ref === 'after')
    expect(next).toMatchObject({ type: 'dropped', balance: (Number(me.balance) - 1000) / 1000 })
    const nonces = dropped.filter((d) => d.player === mover.session.playerId).map((d) => d.nonce)
    expect(nonces).not.toContain(next.nonce)
    await onB.take((m) => m.type === 'settled' && m.dropId === next.dropId)
    expect(await ledgerMismatches(databaseUrl, START)).toEqual([])
    void c
  })
})
