import { describe, it, expect, beforeAll } from 'vitest'
import { createHash } from 'node:crypto'
import { createBoard, DropSimulator, ENGINE_VERSIONS, sha256Hex } from '../../engine/index.js'
import { FlightHasher } from '../../protocol/drop-events-codec.js'
import { shareTokenMessage, shareTokenOf } from '../../protocol/share-token.js'
import { useServerOn, eventually } from './helpers/server.js'

/**
 * The seeds delivery (join with delivery "seeds"): no position frames, the
 * other players' drops in drop-events frames at most every 60 / EVENT_HZ
 * ticks, a desync check whose hash a page can recompute from the seeds
 * alone, nothing when nothing happens. The server is real (SQLite ledger,
 * real sockets), run at TEST_TICK_RATE.
 */

/** The flight hash a page computes at `tick` from the drops it knows, each replayed alone from its seed. */
function pageFlightHash (board, tick, drops) {
  const known = [...new Map(drops.map((d) => [d.dropId, d])).values()]
  const inFlight = []
  for (const drop of known) {
    const simulator = new DropSimulator(board)
    const id = simulator.addDrop(drop.dropSeed)
    let landed = false
    for (let t = 0; t < tick - drop.startTick && !landed; t++) landed = simulator.step().length > 0
    const world = simulator.world
    if (!landed) inFlight.push([drop.slot, world.xOf(id), world.yOf(id), world.vxOf(id), world.vyOf(id)])
  }
  inFlight.sort((a, b) => a[0] - b[0])
  const hasher = new FlightHasher().begin(tick)
  for (const ball of inFlight) hasher.add(...ball)
  return hasher.digest()
}

/**
 * Whether `ticks` all fall on one grid of `every` ticks, each at most `every >> 1`
 * ticks after a grid tick (a due frame waits up to half a period for a commit in
 * progress: delivery-seeds.js).
 */
function onOneGrid (ticks, every) {
  const hold = every >> 1
  for (let phase = 0; phase < every; phase++) {
    if (ticks.every((tick) => (((tick - phase) % every) + every) % every <= hold)) return true
  }
  return false
}

const boardOf = (joined) => createBoard({ rows: joined.board.rows, risk: joined.board.risk, engineVersion: joined.engineVersion })

async function roomState (server, id) {
  const { body } = await server.api('GET', '/api/rooms')
  return body.rooms.find((room) => room.id === id)
}

describe('seeds delivery', () => {
  const context = useServerOn('sqlite')
  let server
  beforeAll(() => { server = context.server })

  it("sends a seeds socket no positions, the other players' drops in frames at most every eventEvery ticks, and a hash the page recomputes from the seeds", async () => {
    const room = '10-low'
    const watcher = await server.player(room, { delivery: 'seeds' })
    const spectator = await server.player(room) // snapshots, in the same room
    const dropper = await server.player(room, { delivery: 'seeds' })
    expect(watcher.client.joined).toMatchObject({ delivery: 'seeds', eventEvery: 15, checkEvery: 120, engineVersions: [...ENGINE_VERSIONS], balls: [] })
    expect(spectator.client.joined.delivery).toBe('snapshots')
    expect(spectator.client.joined.eventEvery).toBeUndefined()

    // Drops spread over several event periods.
    const own = []
    for (let i = 0; i < 4; i++) {
      dropper.client.send({ type: 'drop', bet: 10 + i, ref: `d${i}` })
      own.push(await dropper.client.take((m) => m.type === 'dropped' && m.ref === `d${i}`))
      await eventually(async () => (await roomState(server, room)).tick > own.at(-1).startTick + 7)
    }
    // The owner's own replies carry its balance, whatever its mode.
    expect(own.map((d) => d.balance)).toEqual([100000 - 10, 100000 - 21, 100000 - 33, 100000 - 46])
    const settled = []
    for (const drop of own) settled.push(await dropper.client.take((m) => m.type === 'settled' && m.dropId === drop.dropId))
    // Balls land in any order: the settled that came last carries the final balance.
    const last = dropper.client.messages.filter((m) => m.type === 'settled').at(-1)
    const milli = (credits) => Math.round(credits * 1000)
    expect(milli(last.balance)).toBe(milli(100000 - 46) + settled.reduce((sum, s) => sum + milli(s.payout), 0))

    const ids = own.map((d) => d.dropId)
    await eventually(() => ids.every((id) => watcher.client.eventFrames.some((f) => f.events.some((e) => e.dropId === id))))
    // Until the room is empty again and the last check (if any) has arrived.
    await eventually(async () => (await roomState(server, room)).ballsInFlight === 0)
    await watcher.client.sync()

    // No positions to seeds sockets; the snapshots socket in the same room still gets them.
    expect(watcher.client.snapshots).toEqual([])
    expect(dropper.client.snapshots).toEqual([])
    expect(spectator.client.snapshots.length).toBeGreaterThan(0)
    // No JSON events of other players either: they come as binary events only.
    expect(watcher.client.messages.filter((m) => m.type === 'dropped' || m.type === 'settled')).toEqual([])
    expect(watcher.client.batches).toEqual([])

    // Each drop once, with exactly the facts of its `dropped`.
    const events = watcher.client.eventFrames.flatMap((f) => f.events)
    expect(events).toEqual(own.map((d) => ({ dropId: d.dropId, bet: d.bet, startTick: d.startTick, slot: d.slot, engineVersion: d.engineVersion, player: d.player, dropSeed: d.dropSeed })))

    // Frames fall on the room's event grid (or up to half a period after a grid tick, waiting
    // for a commit), at most one per eventEvery ticks; a frame without events (a check alone)
    // only checkEvery ticks after the previous frame.
    const frames = watcher.client.eventFrames
    expect(onOneGrid(frames.map((f) => f.tick), 15)).toBe(true)
    for (let i = 1; i < frames.length; i++) {
      const gap = frames[i].tick - frames[i - 1].tick
      expect(gap).toBeGreaterThanOrEqual((frames[i].events.length > 0 ? 15 : 120) - (15 >> 1))
    }
    // Every frame's hash is what a page computes from the drops it knows by then.
    const board = boardOf(watcher.client.joined)
    const known = []
    for (const frame of frames) {
      known.push(...frame.events)
      expect(pageFlightHash(board, frame.tick, known)).toBe(frame.hash)
    }
    // The dropper got the same frames, but for those holding nothing but its own drops (it had
    // them in its `dropped`) unless they carry its own `settled`, and besides them only frames
    // that carry its own `settled` (the owner's section) with no events.
    const dropperFrames = dropper.client.eventFrames
    const everyones = dropperFrames.filter((f) => frames.some((w) => w.tick === f.tick))
    const ownOnly = (f) => f.events.length > 0 && f.events.every((e) => e.player === dropper.client.welcome.playerId)
    expect(everyones.map((f) => f.hash)).toEqual(frames.filter((w) => !ownOnly(w) || dropperFrames.some((f) => f.tick === w.tick)).map((f) => f.hash))
    for (const f of everyones) if (ownOnly(f)) expect(f.own.length).toBeGreaterThan(0)
    expect(frames.some(ownOnly)).toBe(true) // the case above happened
    for (const f of dropperFrames.filter((d) => !everyones.includes(d))) {
      expect(f.events).toEqual([])
      expect(f.own.length).toBeGreaterThan(0)
      expect(f.own.every((m) => m.type === 'settled')).toBe(true)
    }
    // Its `settled` came in those frames, never on its own, each on the room's event grid
    // after the ball landed; the watcher's frames carry no one else's.
    const ownSettled = dropper.client.messages.filter((m) => m.type === 'settled')
    expect(ownSettled.map((m) => m.dropId).sort()).toEqual([...ids].sort())
    for (const m of ownSettled) expect(m.viaFrame).toBeGreaterThanOrEqual(m.tick)
    expect(onOneGrid([...frames.map((f) => f.tick), ...ownSettled.map((m) => m.viaFrame)], 15)).toBe(true)
    expect(frames.every((f) => f.own.length === 0)).toBe(true)
    await Promise.all([watcher.client.close(), spectator.client.close(), dropper.client.close()])
  })

  it('sends nothing to a seeds socket while nothing happens in its room', async () => {
    const room = '9-medium'
    const watcher = await server.player(room, { delivery: 'seeds' })
    const dropper = await server.player(room, { delivery: 'seeds' })
    dropper.client.send({ type: 'drop', bet: 1, ref: 'one' })
    const dropped = await dropper.client.take((m) => m.ref === 'one')
    await dropper.client.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    await eventually(async () => (await roomState(server, room)).ballsInFlight === 0)
    await watcher.client.sync()
    const framesBefore = watcher.client.eventFrames.length
    expect(framesBefore).toBeGreaterThan(0)
    const { tick } = await roomState(server, room)
    // Three desync-check periods of an empty room.
    await eventually(async () => (await roomState(server, room)).tick > tick + 3 * 120, { timeoutMs: 20_000 })
    await watcher.client.sync()
    expect(watcher.client.eventFrames.length).toBe(framesBefore)
    expect(watcher.client.snapshots).toEqual([])
    await Promise.all([watcher.client.close(), dropper.client.close()])
  })

  it('gives a late seeds joiner every ball in flight and the room tick, so it fast-forwards them to the server\'s state', async () => {
    const room = '16-high'
    const dropper = await server.player(room, { delivery: 'seeds' })
    const own = []
    for (let i = 0; i < 3; i++) {
      dropper.client.send({ type: 'drop', bet: 5, ref: `late${i}` })
      own.push(await dropper.client.take((m) => m.ref === `late${i}`))
    }
    const late = await server.player(room, { delivery: 'seeds' })
    const { joined } = late.client
    expect(joined.tick).toBeGreaterThanOrEqual(Math.max(...own.map((d) => d.startTick)))
    // Every announced ball in flight (on a 16-row board none has landed yet).
    expect(joined.balls.map((b) => b.dropId).sort()).toEqual(own.map((d) => d.dropId).sort())
    for (const ball of joined.balls) {
      const drop = own.find((d) => d.dropId === ball.dropId)
      expect(ball).toMatchObject({ slot: drop.slot, dropSeed: drop.dropSeed, engineVersion: drop.engineVersion, startTick: drop.startTick })
    }
    // Its first frame (events or a check) hashes the state the joiner reaches from joined.balls.
    await eventually(() => late.client.eventFrames.length > 0)
    const [frame] = late.client.eventFrames
    expect(pageFlightHash(boardOf(joined), frame.tick, [...joined.balls, ...frame.events])).toBe(frame.hash)
    await Promise.all([dropper.client.close(), late.client.close()])
  })

  it('refuses an unknown delivery with E_BAD_DELIVERY and keeps the socket; a socket can switch a room to snapshots by joining again', async () => {
    const { client } = await server.player()
    const error = await client.expectError({ type: 'join', room: '8-low', delivery: 'frames', ref: 7 })
    expect(error).toMatchObject({ code: 'E_BAD_DELIVERY', ref: 7 })
    client.send({ type: 'join', room: '8-low', delivery: 'seeds' })
    expect(await client.take('joined')).toMatchObject({ room: '8-low', delivery: 'seeds' })
    // What a page does on a desync: the same room, now with positions.
    client.send({ type: 'join', room: '8-low', delivery: 'snapshots' })
    expect(await client.take('joined')).toMatchObject({ room: '8-low', delivery: 'snapshots' })
    client.send({ type: 'drop', bet: 1, ref: 's' })
    await client.take((m) => m.ref === 's')
    await eventually(() => client.snapshots.length > 0)
    expect((await roomState(server, '8-low')).players).toBe(1)
    await client.close()
  })

  it("serves another player's drop to a seeds watcher through its share link, with the token of the seed its frame announced", async () => {
    const watcher = await server.player('11-medium', { delivery: 'seeds' })
    const { client, session } = await server.player('11-medium', { delivery: 'seeds' })
    client.send({ type: 'drop', bet: 3, ref: 'p' })
    const dropped = await client.take((m) => m.ref === 'p')
    const settled = await client.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    // All the watcher has of it: the drop-events frame's entry (its seed among them), no `dropped` or `settled`.
    await eventually(() => watcher.client.eventFrames.some((f) => f.events.some((e) => e.dropId === dropped.dropId)))
    const event = watcher.client.eventFrames.flatMap((f) => f.events).find((e) => e.dropId === dropped.dropId)
    expect(watcher.client.messages.filter((m) => m.dropId === dropped.dropId)).toEqual([])
    // The token as the page computes it: WebCrypto (the engine's sha256Hex) over the protocol's rule, with no session.
    const token = shareTokenOf(await sha256Hex(shareTokenMessage(event.dropSeed)))
    const reply = await server.api('GET', `/api/share/${event.dropId}/${token}`)
    expect(reply.status).toBe(200)
    expect(reply.body).toMatchObject({
      id: dropped.dropId,
      player: `${dropped.player.slice(0, 6)}…`,
      room: '11-medium',
      rows: 11,
      risk: 'medium',
      engineVersion: dropped.engineVersion,
      serverSeedHash: dropped.serverSeedHash,
      clientSeed: dropped.clientSeed,
      nonce: dropped.nonce,
      dropSeed: event.dropSeed,
      bet: 3,
      status: 'settled',
      bucket: settled.bucket,
      multiplier: settled.multiplier,
      payout: settled.payout,
      ticks: settled.ticks,
      stateHash: settled.stateHash,
      serverSeed: null,
      verifiable: false
    })
    // Never the whole player id.
    expect(JSON.stringify(reply.body)).not.toContain(dropped.player)
    // Once the player rotates that seed it is public: the record then carries it, and it hashes to the commitment.
    const rotated = await server.api('POST', '/api/seeds/rotate', { token: session.token })
    expect(rotated.status).toBe(200)
    const revealed = (await server.api('GET', `/api/share/${event.dropId}/${token}`)).body
    expect(revealed).toMatchObject({ serverSeed: rotated.body.previousServerSeed, verifiable: true })
    expect(createHash('sha256').update(revealed.serverSeed).digest('hex')).toBe(dropped.serverSeedHash)
    await Promise.all([watcher.client.close(), client.close()])
  })
})

describe('seeds delivery at EVENT_HZ=12', () => {
  const context = useServerOn('sqlite', { env: { EVENT_HZ: '12' } })

  it('paces the drop-events frames at 60 / EVENT_HZ ticks', async () => {
    const server = context.server
    const watcher = await server.player('13-low', { delivery: 'seeds' })
    const dropper = await server.player('13-low')
    expect(watcher.client.joined.eventEvery).toBe(5)
    for (let i = 0; i < 3; i++) {
      dropper.client.send({ type: 'drop', bet: 1, ref: `f${i}` })
      await dropper.client.take((m) => m.ref === `f${i}`)
    }
    await eventually(() => watcher.client.eventFrames.flatMap((f) => f.events).length === 3)
    const ticks = watcher.client.eventFrames.map((f) => f.tick)
    expect(onOneGrid(ticks, 5)).toBe(true)
    for (let i = 1; i < ticks.length; i++) expect(ticks[i] - ticks[i - 1]).toBeGreaterThanOrEqual(5 - (5 >> 1))
    await Promise.all([watcher.client.close(), dropper.client.close()])
  })
})
