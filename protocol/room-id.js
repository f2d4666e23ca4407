import { MIN_ROWS, MAX_ROWS, RISKS } from '../engine/board.js'

/**
 * Room ids, one module for the server and the browser (served at /protocol/).
 * A room id names the board and the instance: `${rows}-${risk}` for the
 * first room of a board (e.g. "16-medium"), `${rows}-${risk}.${n}` for the
 * others (n = 2..ROOM_INSTANCES), so the players of one board can spread
 * over several rooms.
 */

/** Rooms per board: `16-medium` is the first, `16-medium.2` … `16-medium.8` the others. */
export const ROOM_INSTANCES = 8
/** Every row count a board can have. */
export const ROWS = Object.freeze(Array.from({ length: MAX_ROWS - MIN_ROWS + 1 }, (_, i) => MIN_ROWS + i))
export { RISKS }

/** @param {number} rows @param {string} risk @param {number} [instance] 1 (the default) .. ROOM_INSTANCES */
export function roomIdOf (rows, risk, instance = 1) {
  return instance === 1 ? `${rows}-${risk}` : `${rows}-${risk}.${instance}`
}

/** Every room id, instance by instance: the first 27 are one room per board, the next 27 the second of each, and so on. */
export const ROOM_IDS = Object.freeze(
  Array.from({ length: ROOM_INSTANCES }, (_, instance) => ROWS.map((rows) => RISKS.map((risk) => roomIdOf(rows, risk, instance + 1))).flat()).flat()
)
const KNOWN = new Set(ROOM_IDS)

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
