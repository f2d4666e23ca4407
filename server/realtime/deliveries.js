import { DELIVERY_MODES, DEFAULT_DELIVERY } from '../../protocol/client-messages.js'
import { snapshotsDelivery } from './delivery-snapshots.js'
import { seedsDelivery } from './delivery-seeds.js'

/**
 * How a socket in a room learns what happens in it: a strategy chosen once,
 * when the socket joins (`join.delivery`), and never asked about again. The
 * room keeps one feed per mode it has sockets of; the game code tells the
 * room what happened (a drop announced, settled, a tick done) and each feed
 * decides what its sockets get.
 *
 * @typedef {object} Delivery
 * @property {string} name as in `join.delivery`
 * @property {(room: import('../rooms/room.js').Room) => RoomFeed} createFeed
 * @property {(room: import('../rooms/room.js').Room) => object} joinedFields the mode's own fields of `joined`
 *
 * @typedef {object} RoomFeed one room's sockets of one mode, and what they are owed
 * @property {Set<import('./connection.js').Connection>} clients
 * @property {(drop: import('../game/drop.js').Drop, text: string) => void} dropAnnounced a drop was recorded (`text`: its `dropped` without balance, JSON)
 * @property {(drop: import('../game/drop.js').Drop, text: string) => void} dropSettled a drop was credited (`text`: its `settled` without balance, JSON)
 * @property {(client: import('./connection.js').Connection, text: string) => void} ownerSettled the owner's `settled`
 *   (JSON with its balance) for one of its sockets in this room: sent now, or held for the room's next frame
 * @property {(client: import('./connection.js').Connection) => void} leave a socket leaves: it is owed nothing more here
 * @property {() => void} beforeJoin a socket is about to get `joined` (its `balls` cover what was announced so far)
 * @property {() => void} flushNow SPECTATOR_EVENTS=immediate: a batch just committed
 * @property {(tally: DeliveryTally) => void} batchCommitted a batch with drops of this room was committed or
 *   refused, between two ticks: what waited for it may go now
 * @property {(tally: DeliveryTally) => void} afterTick the room stepped: send what is due
 *
 * @typedef {object} DeliveryTally frames written since the last tick began (by the tick, then by commits
 *   done before the next one), counted once per room (one metrics update per tick)
 * @property {number} snapshotFrames @property {number} snapshotBytes
 * @property {number} eventFrames @property {number} eventBytes
 */

/** @type {Record<string, Delivery>} */
const DELIVERIES = { snapshots: snapshotsDelivery, seeds: seedsDelivery }
if (DELIVERY_MODES.some((name) => !DELIVERIES[name])) throw new Error('a delivery mode of protocol/client-messages.js has no implementation')

/**
 * @param {string} [name] `join.delivery`, already checked against its schema
 * @returns {Delivery}
 */
export function deliveryNamed (name = DEFAULT_DELIVERY) {
  return DELIVERIES[name]
}

/** @returns {DeliveryTally} */
export function emptyTally () {
  return { snapshotFrames: 0, snapshotBytes: 0, eventFrames: 0, eventBytes: 0 }
}
