import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { MODES, coordinationTestbed, itWithOtherProcesses } from './helpers/coordination.js'
import { RoomRegistry } from '../../server/rooms/room-registry.js'
import { KEYS } from '../../server/cluster/room-directory.js'
import { eventually } from '../../tools/eventually.js'

/**
 * The room ownership contract (server/coordination/room-ownership.js), run
 * against both modes with the real room registry. Alone every room is this
 * process's; clustered a room is one process's at a time, the others are
 * told where it runs, and a lease lost is reported through `onRoomLost`
 * (ownership never touches a room itself).
 */
describe.each(MODES)('the room ownership contract: $name', (entry) => {
  const testbed = coordinationTestbed(entry)
  beforeAll(() => testbed.setup(), 120_000)
  afterAll(() => testbed.teardown(), 60_000)

  /** A process whose ownership is started with a real registry; `lost` collects onRoomLost. */
  async function started () {
    const process = await testbed.process()
    const rooms = new RoomRegistry({ snapshotEvery: 6, onChange: (room) => { if (rooms.get(room.id) !== room) process.ownership.disposed(room.id) } })
    const lost = []
    await process.ownership.start({ rooms, ledger: { run: (work) => work() }, onRoomLost: (roomId) => lost.push(roomId) })
    process.ownership.setListenUrl(process.config.publicUrl)
    return { ...process, rooms, lost }
  }

  it('claims a free room, then owns it and lists it as the registry summarises it', async () => {
    const process = await started()
    await process.ownership.claim('16-medium')
    expect(process.ownership.owns('16-medium')).toBe(true)
    const room = process.rooms.getOrCreate('16-medium')
    await process.ownership.heartbeat?.()
    const listed = (await process.ownership.list()).find((r) => r.id === '16-medium')
    expect(listed).toMatchObject(room.summary())
    expect(process.lost).toEqual([])
  })

  it('keeps a room that comes back (joined while still owned) before its lease is given up', async () => {
    const process = await started()
    await process.ownership.claim('8-low')
    process.rooms.getOrCreate('8-low')
    process.rooms.disposeIdle()
    expect(process.rooms.get('8-low')).toBeUndefined()
    // As the arena does on a join: still owned, so the room is created at once, in the same call stack.
    expect(process.ownership.owns('8-low')).toBe(true)
    process.rooms.getOrCreate('8-low')
    await process.ownership.heartbeat?.()
    expect(process.ownership.owns('8-low')).toBe(true)
    expect(process.lost).toEqual([])
  })

  it('claims a room again once it was disposed and let go', async () => {
    const process = await started()
    await process.ownership.claim('10-medium')
    process.rooms.getOrCreate('10-medium')
    process.rooms.disposeIdle()
    // Alone a room is never given up; clustered its lease is released behind the ledger queue, then in Redis (polled).
    if (entry.redis) await eventually(async () => !process.ownership.owns('10-medium') && (await readLease(testbed.redis().url, '10-medium')) === null)
    await process.ownership.claim('10-medium')
    expect(process.ownership.owns('10-medium')).toBe(true)
  })

  itWithOtherProcesses(entry)('refuses a room another process holds with where it runs, and hands it over once released', async () => {
    const [a, b] = [await started(), await started()]
    await a.ownership.claim('12-high')
    a.rooms.getOrCreate('12-high')
    expect(b.ownership.owns('12-high')).toBe(false)
    const refused = await b.ownership.claim('12-high').catch((error) => error)
    expect(refused).toMatchObject({ code: 'E_WRONG_NODE', details: { room: '12-high', owner: a.config.publicUrl } })
    const listedByB = (await b.ownership.list()).find((r) => r.id === '12-high')
    expect(listedByB).toMatchObject({ id: '12-high', owner: a.config.publicUrl })

    a.rooms.disposeIdle()
    const redis = testbed.redis()
    await eventually(async () => (await readLease(redis.url, '12-high')) === null)
    await b.ownership.claim('12-high')
    expect(b.ownership.owns('12-high')).toBe(true)
  })

  itWithOtherProcesses(entry)('reports a lease taken by another process through onRoomLost, and owns the room no more', async () => {
    const process = await started()
    await process.ownership.claim('14-low')
    process.rooms.getOrCreate('14-low')
    await overwriteLease(testbed.redis().url, '14-low', 'another-node')
    await process.ownership.heartbeat()
    expect(process.lost).toEqual(['14-low'])
    expect(process.ownership.owns('14-low')).toBe(false)
  })
})

async function withRedis (url, work) {
  const { default: Redis } = await import('ioredis')
  const redis = new Redis(url)
  try {
    return await work(redis)
  } finally {
    await redis.quit()
  }
}

const readLease = (url, roomId) => withRedis(url, (redis) => redis.get(KEYS.lease(roomId)))
const overwriteLease = (url, roomId, owner) => withRedis(url, (redis) => redis.set(KEYS.lease(roomId), owner, 'PX', 60_000))
