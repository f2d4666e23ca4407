/**
 * Every JSON message the server sends, built in one place (the binary
 * frames are protocol/snapshot-codec.js and protocol/drop-events-codec.js).
 * Plain functions of plain facts: no server object is imported, so the
 * builders are what server/realtime/asyncapi-document.js describes and what
 * tests/docs/websocket-protocol.test.js checks real sessions against.
 * Money arrives here already in credits.
 */

/**
 * @param {{ playerId: string, balance: number, serverSeedHash: string, clientSeed: string, nonce: number, engineVersion: string, tickRate: number, minBet: number, maxBet: number }} facts
 */
export function welcomeMessage ({ playerId, balance, serverSeedHash, clientSeed, nonce, engineVersion, tickRate, minBet, maxBet }) {
  return { type: 'welcome', playerId, balance, serverSeedHash, clientSeed, nonce, engineVersion, tickRate, minBet, maxBet }
}

/**
 * The reply to `join`: the room, its board and every announced ball in
 * flight with what a late joiner needs to fast-forward it from its seed
 * (slot, drop seed, engine version, start tick), and the room's tick.
 * `delivery` is the socket's mode; `extra` its mode's own fields (seeds:
 * eventEvery, checkEvery, engineVersions).
 * @param {{ room: string, delivery: string, board: object, tick: number, tickRate: number, snapshotEvery: number, engineVersion: string, balls: object[] }} facts
 * @param {object} [extra]
 */
export function joinedMessage ({ room, delivery, board, tick, tickRate, snapshotEvery, engineVersion, balls }, extra) {
  return { type: 'joined', room, delivery, board, tick, tickRate, snapshotEvery, engineVersion, balls, ...extra }
}

/** @param {string} room */
export function leftMessage (room) {
  return { type: 'left', room }
}

/**
 * The reply to `ping`. A socket in a room also gets the room's tick as it
 * answers: one more sample for the page's room clock, in a room where
 * nothing else names a tick for a while.
 * @param {number} serverTime epoch ms
 * @param {{ id: string, tick: number } | null} [room] the socket's room
 */
export function pongMessage (serverTime, room = null) {
  return room ? { type: 'pong', serverTime, room: room.id, tick: room.tick } : { type: 'pong', serverTime }
}

/**
 * @param {string} code @param {string} message
 * @param {object} [details] extra fields, e.g. `room` and `owner` of E_WRONG_NODE
 */
export function errorMessage (code, message, details) {
  return { type: 'error', code, message, ...details }
}

/**
 * What every player may know of a drop: enough to replay its ball from its seed.
 * @param {{ id: number, playerId: string, slot: number, serverSeedHash: string, clientSeed: string, nonce: number, dropSeed: string, engineVersion: string, bet: number, startTick: number }} drop
 */
export function publicDropFacts (drop) {
  return {
    dropId: drop.id,
    player: drop.playerId,
    slot: drop.slot,
    serverSeedHash: drop.serverSeedHash,
    clientSeed: drop.clientSeed,
    nonce: drop.nonce,
    dropSeed: drop.dropSeed,
    engineVersion: drop.engineVersion,
    bet: drop.bet,
    startTick: drop.startTick
  }
}

/** The `dropped` message (without the owner's balance). @param {Parameters<typeof publicDropFacts>[0] & { roomId: string }} drop */
export function droppedMessage (drop) {
  return { type: 'dropped', room: drop.roomId, ...publicDropFacts(drop) }
}

/**
 * The `settled` message (without the owner's balance).
 * @param {{ roomId: string, id: number, playerId: string, bet: number }} drop
 * @param {{ bucket: number, multiplier: number, ticks: number, tick: number, stateHash: string }} outcome
 * @param {number} payout credits
 */
export function settledMessage (drop, { bucket, multiplier, ticks, tick, stateHash }, payout) {
  return { type: 'settled', room: drop.roomId, dropId: drop.id, player: drop.playerId, bet: drop.bet, bucket, multiplier, payout, ticks, tick, stateHash }
}

/**
 * The `events` message as JSON text, around `events`, a JSON array text of
 * `dropped`/`settled` messages (already encoded once for the room's frame).
 * @param {string} room @param {string} events
 */
export function eventsMessageText (room, events) {
  return `{"type":"events","room":${JSON.stringify(room)},"events":${events}}`
}

/** Clustered: another process changed this player's committed balance. @param {number} balance credits */
export function balanceMessage (balance) {
  return { type: 'balance', balance }
}
