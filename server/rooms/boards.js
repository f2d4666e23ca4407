import { createBoard, ENGINE_VERSION } from '../../engine/index.js'
import { parseRoomId, roomIdOf } from '../../protocol/room-id.js'

const boards = new Map()

/**
 * The (frozen, shared) board of a room id under an engine version; boards
 * are built once per process and shared by a board's instances (and so are
 * its pegs: DropSimulator). Rooms run the newest version; older ones replay
 * and audit the drops recorded under them.
 * @param {string} id a valid room id (protocol/room-id.js)
 * @param {string} [engineVersion] default the newest
 * @throws {import('../../engine/index.js').UnknownEngineVersionError}
 */
export function boardOf (id, engineVersion = ENGINE_VERSION) {
  const parsed = parseRoomId(id)
  if (!parsed) throw new RangeError(`no room ${id}`)
  const key = `${roomIdOf(parsed.rows, parsed.risk)}@${engineVersion}`
  let board = boards.get(key)
  if (!board) {
    board = createBoard({ rows: parsed.rows, risk: parsed.risk, engineVersion })
    boards.set(key, board)
  }
  return board
}
