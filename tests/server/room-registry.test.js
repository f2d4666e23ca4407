import { describe, it, expect } from 'vitest'
import { RoomRegistry } from '../../server/rooms/room-registry.js'

const ids = (rooms) => rooms.map((room) => room.id)

describe('RoomRegistry: the order a tick steps the rooms', () => {
  it('puts the rooms of one board together, boards in the order their first room came, rooms in creation order', () => {
    const registry = new RoomRegistry({ snapshotEvery: 3 })
    for (const id of ['16-low', '8-high', '16-low.2', '12-medium', '8-high.2', '16-low.3', '12-medium.2']) registry.getOrCreate(id)
    expect(ids([...registry.values()])).toEqual(['16-low', '8-high', '16-low.2', '12-medium', '8-high.2', '16-low.3', '12-medium.2'])
    expect(ids(registry.inStepOrder())).toEqual(['16-low', '16-low.2', '16-low.3', '8-high', '8-high.2', '12-medium', '12-medium.2'])
    // Every room on a board shares that board (one grid in the cache for all of them).
    expect(registry.get('16-low.3').board).toBe(registry.get('16-low').board)
  })

  it('follows every change: a room created, removed, adopted or disposed', () => {
    const changes = []
    const registry = new RoomRegistry({ snapshotEvery: 3, onChange: (room) => changes.push(room.id) })
    registry.getOrCreate('10-low')
    registry.getOrCreate('14-high')
    expect(ids(registry.inStepOrder())).toEqual(['10-low', '14-high'])
    registry.getOrCreate('10-low.2')
    expect(ids(registry.inStepOrder())).toEqual(['10-low', '10-low.2', '14-high'])
    // Boards in the order of their first room still alive.
    registry.remove('10-low')
    expect(ids(registry.inStepOrder())).toEqual(['14-high', '10-low.2'])
    const other = new RoomRegistry({ snapshotEvery: 3 }).getOrCreate('14-high.2')
    registry.adopt(other)
    expect(ids(registry.inStepOrder())).toEqual(['14-high', '14-high.2', '10-low.2'])
    // No clients and no balls: all idle, all disposed.
    registry.disposeIdle()
    expect(registry.inStepOrder()).toEqual([])
    expect(changes).toEqual(['10-low', '14-high', '10-low.2', '10-low', '14-high.2', '14-high', '10-low.2', '14-high.2'])
  })
})
