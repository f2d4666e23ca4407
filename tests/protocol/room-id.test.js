import { describe, it, expect } from 'vitest'
import { ROOM_IDS, ROOM_INSTANCES, ROWS, RISKS, parseRoomId, roomIdOf } from '../../protocol/room-id.js'
import { MIN_ROWS, MAX_ROWS } from '../../engine/board.js'

describe('room ids (protocol/room-id.js)', () => {
  it('name every board and instance once, one room per board first', () => {
    expect(ROWS).toEqual(Array.from({ length: MAX_ROWS - MIN_ROWS + 1 }, (_, i) => MIN_ROWS + i))
    expect(ROOM_IDS).toHaveLength(ROWS.length * RISKS.length * ROOM_INSTANCES)
    expect(new Set(ROOM_IDS).size).toBe(ROOM_IDS.length)
    expect(ROOM_IDS.slice(0, 3)).toEqual(['8-low', '8-medium', '8-high'])
    expect(ROOM_IDS[27]).toBe('8-low.2')
  })

  it('parse every id they list back to its board and instance, and no other id', () => {
    for (const id of ROOM_IDS) {
      const parsed = parseRoomId(id)
      expect(roomIdOf(parsed.rows, parsed.risk, parsed.instance)).toBe(id)
    }
    for (const id of ['16-medium.1', '16-medium.9', '16-medium.02', '7-low', '17-high.2', '16-extreme', '', null, 16, '16-medium ']) {
      expect(parseRoomId(id), String(id)).toBeNull()
    }
  })
})
