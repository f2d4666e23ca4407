import { simulateDrop, ENGINE_VERSION } from '/engine/index.js'
import { BoardCache } from './board-cache.js'

/**
 * Verifies every drop the page hears about with the very engine the server
 * runs, under the engine version the drop was decided under: on `dropped`
 * the drop is simulated from its drop seed, and when its
 * `settled` (or its ledger record) arrives, bucket, ticks and the hash of
 * the ball's exact final state must all be equal. In seeds mode the drop
 * is not simulated ahead: the ball drawn on the board is (seeded-room.js),
 * and its landing fills in the outcome the settlement is compared with.
 */

/**
 * @typedef {object} LocalDrop
 * @property {number} dropId @property {string} player @property {boolean} mine
 * @property {string} room @property {number} rows @property {string} risk @property {string} engineVersion
 * @property {string} dropSeed @property {number} startTick @property {number} slot
 * @property {number | null} bucket @property {number | null} ticks @property {string | null} stateHash  the local outcome (null: not simulated to its landing yet)
 * @property {Float64Array | null} trajectory x, y, angle per tick from release (null: checked from a record, not shown)
 * @property {number} [bet] whole credits, when announced
 */

/**
 * @typedef {object} Verification
 * @property {number} dropId @property {string} player @property {boolean} mine @property {string} room
 * @property {number} localBucket @property {number} serverBucket
 * @property {number} localTicks @property {number} serverTicks
 * @property {string} localStateHash @property {string} serverStateHash
 * @property {boolean} verified bucket, ticks and stateHash all equal
 * @property {'live' | 'ledger'} source a `settled` message, or the player's stored record (an earlier visit, or settled while disconnected)
 */

/** Verifications kept for display and tests; older ones are only counted. */
const MAX_KEPT = 10_000

export class DropVerifier {
  constructor () {
    this._boards = new BoardCache()
    /** @type {Map<number, LocalDrop>} simulated, not yet settled */
    this.pending = new Map()
    /** @type {Verification[]} in settlement order (the latest MAX_KEPT) */
    this.results = []
    this.total = 0
    /** @type {Map<number, Verification>} */
    this.byId = new Map()
    this.failures = 0
  }

  /**
   * The engine's board, built locally (not taken from the server), once.
   * @param {number} rows @param {string} risk @param {string} [engineVersion] default the page's newest
   * @throws {import('/engine/index.js').UnknownEngineVersionError} a version this page's engine does not have
   */
  board (rows, risk, engineVersion) {
    return this._boards.board(rows, risk, engineVersion)
  }

  /**
   * Simulates an announced drop (once per drop id).
   * @param {{ dropId: number, player: string, room: string, dropSeed: string, engineVersion?: string, startTick: number, slot: number }} announced
   * @param {{ rows: number, risk: string }} boardOf rows and risk of the drop's room
   * @param {string | null} playerId the viewer
   * @returns {LocalDrop}
   */
  simulate (announced, { rows, risk }, playerId) {
    const known = this.pending.get(announced.dropId)
    if (known && known.trajectory) return known
    const engineVersion = announced.engineVersion ?? ENGINE_VERSION
    const board = this.board(rows, risk, engineVersion)
    const outcome = simulateDrop(board, announced.dropSeed, { trajectory: true })
    if (known) {
      // Expected in seeds mode, now shown from snapshots (the room was switched): the whole path is needed at once.
      Object.assign(known, { bucket: outcome.bucket, ticks: outcome.ticks, stateHash: outcome.stateHash, trajectory: outcome.trajectory })
      return known
    }
    const local = localDrop(announced, { rows, risk, engineVersion }, playerId, outcome)
    if (!this.byId.has(local.dropId)) this.pending.set(local.dropId, local)
    return local
  }

  /**
   * An announced drop whose outcome the page's live simulation will give
   * (seeds mode): the drop without its outcome, to be filled in by the
   * simulation that draws it. Only the player's own drops are kept for
   * verification: in seeds mode only their settlements reach the page
   * (another player's is checked by the room's desync check).
   * @param {{ dropId: number, player: string, room: string, dropSeed: string, engineVersion?: string, startTick: number, slot: number, bet?: number }} announced
   * @param {{ rows: number, risk: string }} boardOf rows and risk of the drop's room
   * @param {string | null} playerId the viewer
   * @returns {LocalDrop}
   */
  expect (announced, { rows, risk }, playerId) {
    const known = this.pending.get(announced.dropId)
    if (known) return known
    const local = localDrop(announced, { rows, risk, engineVersion: announced.engineVersion ?? ENGINE_VERSION }, playerId, null)
    if (local.mine && !this.byId.has(local.dropId)) this.pending.set(local.dropId, local)
    return local
  }

  /**
   * Compares a `settled` message with the local simulation.
   * @param {{ dropId: number, bucket: number, ticks: number, stateHash: string }} settled
   * @returns {Verification | null} null when this drop was never simulated here
   */
  settle (settled) {
    return this.byId.get(settled.dropId) ?? this._compare(settled, 'live')
  }

  /**
   * Compares a settled ledger record of the player's (GET /api/drops): a
   * drop whose `settled` message was missed while reconnecting, or one from
   * an earlier visit, simulated now if it was not before.
   * @param {{ id: number, bucket: number, ticks: number, stateHash: string, status: string }} record
   */
  settleFromRecord (record) {
    if (record.status !== 'settled' || this.byId.has(record.id)) return this.byId.get(record.id) ?? null
    if (!this.pending.has(record.id)) {
      const outcome = simulateDrop(this.board(record.rows, record.risk, record.engineVersion), record.dropSeed)
      this.pending.set(record.id, {
        dropId: record.id,
        player: record.playerId,
        mine: true,
        room: record.room,
        rows: record.rows,
        risk: record.risk,
        engineVersion: record.engineVersion,
        dropSeed: record.dropSeed,
        startTick: record.startTick,
        slot: -1,
        bucket: outcome.bucket,
        ticks: outcome.ticks,
        stateHash: outcome.stateHash,
        trajectory: null
      })
    }
    return this._compare({ dropId: record.id, bucket: record.bucket, ticks: record.ticks, stateHash: record.stateHash }, 'ledger')
  }

  /** Forgets unsettled drops that match `predicate` (their settlement will never reach this page). */
  forget (predicate) {
    for (const [dropId, local] of this.pending) if (predicate(local)) this.pending.delete(dropId)
  }

  _compare ({ dropId, bucket, ticks, stateHash }, source) {
    const local = this.pending.get(dropId)
    if (!local) return null
    this.pending.delete(dropId)
    if (local.ticks === null) {
      // Expected (seeds mode) but not simulated to its landing here (the room was left): simulate it now.
      const outcome = simulateDrop(this.board(local.rows, local.risk, local.engineVersion), local.dropSeed)
      local.bucket = outcome.bucket
      local.ticks = outcome.ticks
      local.stateHash = outcome.stateHash
    }
    /** @type {Verification} */
    const verification = {
      dropId,
      player: local.player,
      mine: local.mine,
      room: local.room,
      localBucket: local.bucket,
      serverBucket: bucket,
      localTicks: local.ticks,
      serverTicks: ticks,
      localStateHash: local.stateHash,
      serverStateHash: stateHash,
      verified: local.bucket === bucket && local.ticks === ticks && local.stateHash === stateHash,
      source
    }
    if (!verification.verified) this.failures++
    this.total++
    this.results.push(verification)
    this.byId.set(dropId, verification)
    if (this.results.length > MAX_KEPT) this.byId.delete(this.results.shift().dropId)
    return verification
  }
}

/**
 * The page's record of an announced drop, with its simulated outcome or,
 * while the live simulation has not landed it, none yet.
 * @param {{ dropId: number, player: string, room: string, dropSeed: string, startTick: number, slot: number, bet?: number }} announced
 * @param {{ rows: number, risk: string, engineVersion: string }} board
 * @param {string | null} playerId the viewer
 * @param {{ bucket: number, ticks: number, stateHash: string, trajectory: Float64Array } | null} outcome
 * @returns {LocalDrop}
 */
function localDrop (announced, { rows, risk, engineVersion }, playerId, outcome) {
  return {
    dropId: announced.dropId,
    player: announced.player,
    mine: announced.player === playerId,
    room: announced.room,
    rows,
    risk,
    engineVersion,
    dropSeed: announced.dropSeed,
    startTick: announced.startTick,
    slot: announced.slot,
    bet: announced.bet,
    bucket: outcome?.bucket ?? null,
    ticks: outcome?.ticks ?? null,
    stateHash: outcome?.stateHash ?? null,
    trajectory: outcome?.trajectory ?? null
  }
}
