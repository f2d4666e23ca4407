import { PAYOUT_RULE } from './money.js'

/**
 * A drop's record shape, in one place: the in-memory drop from acceptance
 * to settlement and the rows the ledger writes for it (what players are
 * told of it is built in protocol/server-messages.js).
 */

/**
 * @typedef {object} Drop one bet on one ball, from acceptance to settlement
 * @property {number} id @property {import('./accounts.js').Account} account
 * @property {string} playerId @property {import('../rooms/room.js').Room} room
 * @property {string} roomId @property {number} rows @property {string} risk
 * @property {string} engineVersion @property {string} seedId @property {string} serverSeedHash
 * @property {string} clientSeed @property {number} nonce @property {string} dropSeed
 * @property {number} bet whole credits @property {number} payoutRule protocol/payout.js
 * @property {number} createdAt ms
 * @property {number} startTick @property {number} slot set by Room.release
 * @property {boolean} announced its row is committed and `dropped` was sent
 * @property {boolean} void its row could not be committed: ignored when it lands
 * @property {{ previous: string } | null} clientSeedChange the drop set a new client seed
 * @property {any} ref the client's ref, echoed to the connection that asked
 * @property {import('../realtime/connection.js').Connection | null} origin
 */

/**
 * @typedef {object} Settlement a landed ball waiting to be written
 * @property {Drop} drop
 * @property {number} bucket @property {number} multiplier @property {number} payout milli-credits
 * @property {number} ticks @property {string} stateHash
 * @property {number} tick room tick at landing (drop.startTick + ticks)
 * @property {number} settledAt ms @property {number} attempts commits tried so far
 */

/**
 * @param {object} facts
 * @param {number} facts.id @param {import('./accounts.js').Account} facts.account
 * @param {import('../rooms/room.js').Room} facts.room @param {number} facts.nonce
 * @param {string} facts.dropSeed @param {number} facts.bet
 * @param {{ previous: string } | null} facts.clientSeedChange
 * @param {any} facts.ref @param {any} facts.origin
 * @returns {Drop}
 */
export function createDrop ({ id, account, room, nonce, dropSeed, bet, clientSeedChange, ref, origin }) {
  return {
    id,
    account,
    playerId: account.playerId,
    room,
    roomId: room.id,
    rows: room.rows,
    risk: room.risk,
    engineVersion: room.board.engineVersion,
    seedId: account.seed.id,
    serverSeedHash: account.seed.hash,
    clientSeed: account.clientSeed,
    nonce,
    dropSeed,
    bet,
    payoutRule: PAYOUT_RULE,
    createdAt: Date.now(),
    startTick: 0,
    slot: -1,
    announced: false,
    void: false,
    clientSeedChange,
    ref,
    origin
  }
}

/** @param {Drop} drop @returns {import('../store/records.js').NewDropRow} */
export function newDropRow (drop) {
  return {
    id: drop.id,
    playerId: drop.playerId,
    room: drop.roomId,
    rows: drop.rows,
    risk: drop.risk,
    engineVersion: drop.engineVersion,
    serverSeedId: drop.seedId,
    serverSeedHash: drop.serverSeedHash,
    clientSeed: drop.clientSeed,
    nonce: drop.nonce,
    dropSeed: drop.dropSeed,
    bet: drop.bet,
    payoutRule: drop.payoutRule,
    startTick: drop.startTick,
    createdAt: drop.createdAt
  }
}

/** @param {Settlement} settlement @returns {import('../store/records.js').SettlementRow} */
export function settlementRow ({ drop, bucket, multiplier, payout, ticks, stateHash, settledAt }) {
  return { id: drop.id, bucket, multiplier, payout, ticks, stateHash, settledAt }
}
