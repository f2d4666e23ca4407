import { createBoard, MIN_ROWS, MAX_ROWS, RISKS, ENGINE_VERSION } from '../../engine/index.js'

/** Rooms per board: `16-medium` is the first, `16-medium.2` … `16-medium.8` the others, so the players of one board can spread over several rooms. */
export const ROOM_INSTANCES = 8

/**
 * Room ids name the board and the instance: `${rows}-${risk}` for the first
 * room of a board (e.g. "16-medium"), `${rows}-${risk}.${n}` for the others
 * (n = 2..ROOM_INSTANCES). Listed instance by instance, so the first 27 are
 * one room per board, the next 27 the second of each, and so on.
 */
export const ROOM_IDS = Object.freeze(
  Array.from({ length: ROOM_INSTANCES }, (_, instance) =>
    Array.from({ length: MAX_ROWS - MIN_ROWS + 1 }, (_, i) => RISKS.map((risk) => roomIdOf(MIN_ROWS + i, risk, instance + 1))).flat()
  ).flat()
)
const KNOWN = new Set(ROOM_IDS)
const boards = new Map()

/**
 * @param {unknown} id
 * @returns {{ rows: number, risk: string, instance: number } | null} null if `id` names no room
 */
export function parseRoomId (id) {
  if (typeof id !== 'string' || !KNOWN.has(id)) return null
  const dash = id.indexOf('-')
  const dot = id.indexOf('.')
  return { rows: Number(id.slice(0, dash)), risk: id.slice(dash + 1, dot < 0 ? undefined : dot), instance: dot < 0 ? 1 : Number(id.slice(dot + 1)) }
}

/** @param {number} rows @param {string} risk @param {number} [instance] 1 (the default) .. ROOM_INSTANCES */
export function roomIdOf (rows, risk, instance = 1) {
  return instance === 1 ? `${rows}-${risk}` : `${rows}-${risk}.${instance}`
}

/**
 * The (frozen, shared) board of a room id under an engine version; boards
 * are built once per process and shared by a board's instances (and so are
 * its pegs: DropSimulator). Rooms run the newest version; older ones replay
 * and audit the drops recorded under them.
 * @param {string} id a valid room id
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
