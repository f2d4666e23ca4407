import { describe, it, expect, beforeAll } from 'vitest'
import { createHash } from 'node:crypto'
import { createBoard, simulateDrop } from '../../engine/index.js'
import { quantizePosition } from '../../protocol/snapshot-codec.js'
import { STORE_KINDS } from './helpers/stores.js'
import { useServerOn, eventually } from './helpers/server.js'

// Money: balances and payouts in milli-credits in the ledger, credits with up to three decimals on the wire.
const payoutMilli = (bet, multiplier) => bet * Math.round(multiplier * 1000)
const milli = (credits) => Math.round(credits * 1000)

describe.each(STORE_KINDS)('gameplay on %s', (kind) => {
  const context = useServerOn(kind)
  const backend = context.backend
  let server
  let database
  beforeAll(() => { ({ server, database } = context) })

  it('creates a guest session with play money and stores only the token hash', async () => {
    const session = await server.session()
    expect(session.token).toMatch(/^[0-9a-f]{64}$/)
    expect(session.serverSeedHash).toMatch(/^[0-9a-f]{64}$/)
    expect(session).toMatchObject({ balance: 100000, nonce: 0 })
    expect(session.clientSeed.length).toBeGreaterThan(0)

    const me = await server.api('GET', '/api/me', { token: session.token })
    expect(me.status).toBe(200)
    expect(me.body).toMatchObject({ playerId: session.playerId, balance: 100000, serverSeedHash: session.serverSeedHash, clientSeed: session.clientSeed, nonce: 0, room: null })

    const rows = await backend.query(database.database, 'SELECT token_hash, balance FROM players WHERE id = $1', [session.playerId])
    expect(rows).toHaveLength(1)
    expect(rows[0].token_hash).toBe(createHash('sha256').update(session.token).digest('hex'))
    expect(rows[0].token_hash).not.toBe(session.token)
    expect(Number(rows[0].balance)).toBe(100000 * 1000)
  })

  it('joins, drops and settles; the ledger, the replay and the snapshots all agree', async () => {
    const room = '12-high'
    const { session, client } = await server.player(room)
    expect(client.joined).toMatchObject({ type: 'joined', room, tickRate: 60, balls: [] })
    expect(client.joined.board).toMatchObject({ rows: 12, risk: 'high' })
    expect(client.joined.board.multipliers).toHaveLength(13)

    const bet = 250
    client.send({ type: 'drop', bet, ref: 'first' })
    const dropped = await client.take('dropped')
    expect(dropped).toMatchObject({ room, player: session.playerId, bet, nonce: 0, serverSeedHash: session.serverSeedHash, clientSeed: session.clientSeed, ref: 'first', balance: 100000 - bet })
    expect(dropped.dropSeed).toMatch(/^[0-9a-f]{64}$/)
    expect(Number.isInteger(dropped.slot)).toBe(true)

    const settled = await client.take('settled')
    expect(settled.dropId).toBe(dropped.dropId)
    // The client-observed start tick plus the ticks in flight is the tick it settled at.
    expect(dropped.startTick + settled.ticks).toBe(settled.tick)
    expect(milli(settled.payout)).toBe(payoutMilli(bet, settled.multiplier))
    expect(milli(settled.balance)).toBe((100000 - bet) * 1000 + payoutMilli(bet, settled.multiplier))

    // The engine replays the drop from its seed alone to the same end.
    const board = createBoard({ rows: 12, risk: 'high' })
    const replay = simulateDrop(board, dropped.dropSeed, { trajectory: true })
    expect({ bucket: replay.bucket, ticks: replay.ticks, stateHash: replay.stateHash, multiplier: replay.multiplier })
      .toEqual({ bucket: settled.bucket, ticks: settled.ticks, stateHash: settled.stateHash, multiplier: settled.multiplier })

    // The ledger row is the same drop.
    const [row] = await backend.query(database.database, 'SELECT * FROM drops WHERE id = $1', [dropped.dropId])
    expect(row).toMatchObject({ player_id: session.playerId, room, rows: 12, risk: 'high', bet, nonce: 0, drop_seed: dropped.dropSeed, bucket: settled.bucket, payout: milli(settled.payout), payout_rule: 2, ticks: settled.ticks, state_hash: settled.stateHash, status: 'settled', start_tick: dropped.startTick })
    const me = await server.api('GET', '/api/me', { token: session.token })
    expect(me.body.balance).toBe(settled.balance)
    expect(me.body.nonce).toBe(1)

    // Every snapshot is the replay at that tick, quantized to 0.5 px; the slot is absent after landing.
    let seen = 0
    for (const snapshot of client.snapshots) {
      const index = [...snapshot.slots].indexOf(dropped.slot)
      const ball = index < 0 ? undefined : { x: snapshot.xs[index], y: snapshot.ys[index] }
      const age = snapshot.tick - dropped.startTick
      if (age >= settled.ticks) {
        expect(ball).toBeUndefined()
        continue
      }
      if (!ball) continue // before `dropped` was sent, the ball is not shown yet
      seen++
      expect(ball.x).toBe(quantizePosition(replay.trajectory[3 * age]) / 2)
      expect(ball.y).toBe(quantizePosition(replay.trajectory[3 * age + 1]) / 2)
    }
    expect(seen).toBeGreaterThan(10)
    await client.close()
  })

  it('keeps balances and the ledger in agreement after many concurrent drops from several players', async () => {
    const players = await Promise.all([0, 1, 2, 3].map((i) => server.player(i < 2 ? '16-medium' : '8-low')))
    const dropsPerPlayer = 15
    const bets = players.map((_, p) => Array.from({ length: dropsPerPlayer }, (_, i) => 1 + ((i * 37 + p * 11) % 400)))
    players.forEach(({ client }, p) => bets[p].forEach((bet) => client.send({ type: 'drop', bet })))

    const outcomes = await Promise.all(players.map(async ({ client }, p) => {
      const dropped = []
      const settled = []
      for (let i = 0; i < dropsPerPlayer; i++) dropped.push(await client.take((m) => m.type === 'dropped' && m.player === players[p].session.playerId))
      for (let i = 0; i < dropsPerPlayer; i++) settled.push(await client.take((m) => m.type === 'settled' && m.player === players[p].session.playerId))
      return { dropped, settled }
    }))

    for (const [p, { session, client }] of players.entries()) {
      const { dropped, settled } = outcomes[p]
      // Every accepted bet was announced once, with consecutive, never-reused nonces.
      expect(dropped.map((d) => d.bet)).toEqual(bets[p])
      expect(dropped.map((d) => d.nonce)).toEqual(Array.from({ length: dropsPerPlayer }, (_, i) => i))
      const expected = (100000 - bets[p].reduce((a, b) => a + b, 0)) * 1000 + settled.reduce((a, s) => a + payoutMilli(s.bet, s.multiplier), 0)
      for (const s of settled) expect(milli(s.payout)).toBe(payoutMilli(s.bet, s.multiplier))

      const me = await server.api('GET', '/api/me', { token: session.token })
      expect(milli(me.body.balance)).toBe(expected)
      const [player] = await backend.query(database.database, 'SELECT balance FROM players WHERE id = $1', [session.playerId])
      expect(Number(player.balance)).toBe(expected)
      const [sums] = await backend.query(database.database,
        "SELECT COUNT(*) AS n, SUM(bet) AS bet, SUM(payout) AS payout FROM drops WHERE player_id = $1 AND status = 'settled'", [session.playerId])
      expect(Number(sums.n)).toBe(dropsPerPlayer)
      expect((100000 - Number(sums.bet)) * 1000 + Number(sums.payout)).toBe(expected)
      expect(client.messages.filter((m) => m.type === 'error')).toEqual([])
    }

    // Everyone in a room sees every ball; only the owner sees the balance.
    const [a, b] = players
    const seenByB = b.client.messages.filter((m) => m.type === 'dropped' && m.player === a.session.playerId)
    expect(seenByB).toHaveLength(dropsPerPlayer)
    for (const m of seenByB) expect(m.balance).toBeUndefined()
    await Promise.all(players.map(({ client }) => client.close()))
  })

  it('gives a late joiner the balls in flight, replayable from their seeds', async () => {
    const room = '10-medium'
    const first = await server.player(room)
    first.client.send({ type: 'drop', bet: 5 })
    const dropped = await first.client.take('dropped')
    const late = await server.player(room)
    const ball = late.client.joined.balls.find((b) => b.dropId === dropped.dropId)
    expect(ball).toMatchObject({ slot: dropped.slot, dropSeed: dropped.dropSeed, startTick: dropped.startTick, nonce: dropped.nonce, player: first.session.playerId, bet: 5 })
    expect(late.client.joined.tick).toBeGreaterThanOrEqual(dropped.startTick)
    const replay = simulateDrop(createBoard({ rows: 10, risk: 'medium' }), ball.dropSeed, { trajectory: true })
    const age = late.client.joined.tick - ball.startTick
    expect(ball.x).toBe(replay.trajectory[3 * age])
    expect(ball.y).toBe(replay.trajectory[3 * age + 1])
    const settled = await late.client.take('settled')
    expect(settled.dropId).toBe(dropped.dropId)
    expect(settled.balance).toBeUndefined()
    await Promise.all([first.client.close(), late.client.close()])
  })

  it('runs a board\'s instance rooms (ROWS-RISK.N) apart, on the same board', async () => {
    const first = await server.player('11-high')
    const second = await server.player('11-high.2')
    expect(second.client.joined.room).toBe('11-high.2')
    expect(second.client.joined.board).toEqual(first.client.joined.board)
    first.client.send({ type: 'drop', bet: 3, ref: 'one' })
    second.client.send({ type: 'drop', bet: 4, ref: 'two' })
    const dropped = await second.client.take((m) => m.ref === 'two')
    expect(dropped.room).toBe('11-high.2')
    const settled = await second.client.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    expect(settled.bucket).toBe(simulateDrop(createBoard({ rows: 11, risk: 'high' }), dropped.dropSeed).bucket)
    await first.client.take((m) => m.type === 'settled' && m.player === first.session.playerId)
    // Each room saw only its own ball.
    expect(second.client.messages.filter((m) => m.type === 'dropped').map((m) => m.player)).toEqual([second.session.playerId])
    expect(first.client.messages.filter((m) => m.type === 'dropped').map((m) => m.player)).toEqual([first.session.playerId])
    for (const bad of ['11-high.1', '11-high.9', '11-high.02', '11-high.']) {
      expect((await second.client.expectError({ type: 'join', room: bad })).code).toBe('E_UNKNOWN_ROOM')
    }
    await Promise.all([first.client.close(), second.client.close()])
  })

  it('lists rooms while in use and disposes them when empty and no ball is in flight', async () => {
    const room = '9-low'
    const { client } = await server.player(room)
    const listed = await server.api('GET', '/api/rooms')
    expect(listed.status).toBe(200)
    expect(listed.body.roomIds).toHaveLength(27 * 8)
    expect(listed.body.roomIds.slice(0, 3)).toEqual(['8-low', '8-medium', '8-high'])
    expect(listed.body.roomIds[27]).toBe('8-low.2')
    expect(listed.body.rooms.find((r) => r.id === room)).toMatchObject({ rows: 9, risk: 'low', players: 1, ballsInFlight: 0 })
    client.send({ type: 'drop', bet: 1 })
    await client.take('dropped')
    client.send({ type: 'leave', ref: 7 })
    expect(await client.take('left')).toEqual({ type: 'left', room, ref: 7 })
    // Empty but a ball is still falling: the room stays until it lands.
    const during = await server.api('GET', '/api/rooms')
    expect(during.body.rooms.find((r) => r.id === room)).toMatchObject({ players: 0, ballsInFlight: 1 })
    // The owner is told about the settlement even after leaving.
    await client.take('settled')
    await eventually(async () => !(await server.api('GET', '/api/rooms')).body.rooms.some((r) => r.id === room))
    await client.close()
  })

  it('answers ping with pong and exposes the metrics', async () => {
    const { client } = await server.player('11-low')
    client.send({ type: 'ping', ref: 'p' })
    const pong = await client.take('pong')
    // In a room, the pong names the room's tick (a room clock sample): never behind what the socket saw before.
    expect(pong).toMatchObject({ type: 'pong', ref: 'p', room: '11-low' })
    expect(pong.tick).toBeGreaterThanOrEqual(client.joined.tick)
    client.send({ type: 'drop', bet: 3 })
    const settled = await client.take('settled')
    client.send({ type: 'ping', ref: 'q' })
    expect((await client.take('pong')).tick).toBeGreaterThanOrEqual(settled.tick)
    client.send({ type: 'leave' })
    await client.take('left')
    client.send({ type: 'ping', ref: 'r' })
    const outside = await client.take('pong')
    expect(outside).toMatchObject({ type: 'pong', ref: 'r' })
    expect(outside.room).toBeUndefined()
    expect(outside.tick).toBeUndefined()
    const response = await server.app.inject({ method: 'GET', url: '/metrics' })
    expect(response.statusCode).toBe(200)
    expect(response.headers['content-type']).toMatch(/^text\/plain/)
    const text = response.body
    const value = (name) => Number(new RegExp(`^${name}(?:\\{[^}]*\\})? (\\S+)$`, 'm').exec(text)?.[1])
    for (const name of ['plinko_rooms', 'plinko_ws_clients', 'plinko_tick_lag_current_seconds', 'plinko_balls_in_flight']) expect(text).toContain(`# TYPE ${name} gauge`)
    for (const name of ['plinko_tick_duration_seconds', 'plinko_tick_lag_seconds', 'plinko_ledger_commit_seconds']) expect(text).toContain(`# TYPE ${name} histogram`)
    expect(text).toContain('plinko_tick_duration_seconds_bucket{le="0.00005"}')
    expect(value('plinko_drops_total')).toBeGreaterThan(0)
    expect(value('plinko_settles_total')).toBeGreaterThan(0)
    expect(value('plinko_ws_bytes_out_total')).toBeGreaterThan(0)
    expect(value('plinko_ticks_total')).toBeGreaterThan(0)
    expect(value('plinko_tick_duration_seconds_count')).toBeGreaterThan(0)
    expect(text).toMatch(/^plinko_ws_messages_in_total\{type="drop"\} [1-9]/m)
    expect(text).toMatch(/^plinko_ws_messages_out_total\{type="snapshot"\} [1-9]/m)
    expect(text).toContain('plinko_snapshots_skipped_total')
    expect(text).toContain('plinko_ticks_dropped_total')
    expect(value('plinko_ws_clients')).toBeGreaterThanOrEqual(1)
    await client.close()
  })
})

describe('how spectators hear of drops (SPECTATOR_EVENTS)', () => {
  for (const mode of ['snapshot', 'immediate']) {
    describe(mode, () => {
      const context = useServerOn('sqlite', { env: { SPECTATOR_EVENTS: mode } })

      it(mode === 'snapshot'
        ? 'sends the other players\' drops with the next snapshot, in one room frame'
        : 'sends the other players\' drops as soon as they are committed, in an events message', async () => {
        const server = context.server
        const dropper = await server.player('14-medium')
        const watcher = await server.player('14-medium')
        dropper.client.send({ type: 'drop', bet: 2, ref: 'w' })
        const own = await dropper.client.take((m) => m.ref === 'w')
        const seen = await watcher.client.take((m) => m.type === 'dropped' && m.dropId === own.dropId)
        expect(seen.balance).toBeUndefined()
        const batch = watcher.client.batches.find((b) => b.events.some((e) => e.dropId === own.dropId))
        expect(batch.via).toBe(mode === 'snapshot' ? 'room frame' : 'events')
        // The dropper's own copy came on its own (with the balance), and it skips its event in the room's batch.
        expect(dropper.client.messages.filter((m) => m.type === 'dropped' && m.dropId === own.dropId)).toHaveLength(1)
        await watcher.client.take((m) => m.type === 'settled' && m.dropId === own.dropId)
        await Promise.all([dropper.client.close(), watcher.client.close()])
      })
    })
  }
})
