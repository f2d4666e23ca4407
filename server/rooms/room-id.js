import { createBoard, MIN_ROWS, MAX_ROWS, RISKS } from '../../engine/index.js'

/**
 * Room ids name the board: `${rows}-${risk}`, e.g. "16-medium". There is one
 * room per board, so at most (MAX_ROWS - MIN_ROWS + 1) × RISKS.length rooms.
 */
export const ROOM_IDS = Object.freeze(
  Array.from({ length: MAX_ROWS - MIN_ROWS + 1 }, (_, i) => RISKS.map((risk) => `${MIN_ROWS + i}-${risk}`)).flat()
)
const KNOWN = new Set(ROOM_IDS)
const boards = new Map()

/**
 * @param {unknown} id
 * @returns {{ rows: number, risk: string } | null} null if `id` names no room
 */
export function parseRoomId (id) {
  if (typeof id !== 'string' || !KNOWN.has(id)) return null
  const dash = id.indexOf('-')
  return { rows: Number(id.slice(0, dash)), risk: id.slice(dash + 1) }
}

/** @param {number} rows @param {string} risk */
export function roomIdOf (rows, risk) {
  return `${rows}-${risk}`
}

/**
 * The (frozen, shared) board of a room id; boards are built once per process.
 * @param {string} id a valid room id
 */
export function boardOf (id) {
  let board = boards.get(id)
  if (!board) {
    const parsed = parseRoomId(id)
    if (!parsed) throw new RangeError(`no room ${id}`)
    boards.set(id, (board = createBoard(parsed)))
  }
  return board
}
