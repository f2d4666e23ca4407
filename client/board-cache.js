import { createBoard, ENGINE_VERSION } from '/engine/index.js'

/**
 * The engine's boards a page (or its board worker) has built, each once:
 * one per table and engine version, built locally (never taken from the
 * server).
 */
export class BoardCache {
  constructor () {
    /** @type {Map<string, import('/engine/board.js').Board>} */
    this._boards = new Map()
  }

  /**
   * @param {number} rows @param {string} risk @param {string} [engineVersion] default the page's newest
   * @throws {import('/engine/index.js').UnknownEngineVersionError} a version this page's engine does not have
   */
  board (rows, risk, engineVersion = ENGINE_VERSION) {
    const key = `${rows}-${risk}@${engineVersion}`
    let board = this._boards.get(key)
    if (!board) this._boards.set(key, (board = createBoard({ rows, risk, engineVersion })))
    return board
  }
}
