/**
 * The page's side of the seeds delivery mode (docs/protocol.md, "Seeds
 * delivery"): which mode the page asks for, what a drop-events frame does
 * to the room (its tick sets the clock, its drops go on the board, its
 * flight hash is checked) and how a desync is reported.
 *
 * A socket in seeds mode gets no position frames: the page draws every
 * ball from its own simulation (seeded-room.js). If the page's hash of the
 * balls in flight ever differs from the server's, the page cannot trust
 * what it draws for that room: it joins it again in snapshots mode, where
 * the server's positions are drawn, and reports the desync
 * (POST /api/client-errors) so that it is seen.
 */
import { decodeDropEvents } from '/protocol/drop-events-codec.js'
import { apiRequest } from './api.js'
import { RoomClock } from './room-clock.js'
import { SeededRoom } from './seeded-room.js'
import { WorkerSeededRoom } from './worker-seeded-room.js'

export const DELIVERY_SEEDS = 'seeds'
export const DELIVERY_SNAPSHOTS = 'snapshots'

/**
 * The mode the page asks for: seeds, unless the address says
 * `?delivery=snapshots` (a thin client, a comparison, a test).
 * @param {string} search location.search
 */
export function pageDelivery (search) {
  return new URLSearchParams(search).get('delivery') === DELIVERY_SNAPSHOTS ? DELIVERY_SNAPSHOTS : DELIVERY_SEEDS
}

/** Whether the room's view is the page's own simulation (here or in the board worker), not the server's snapshots. */
export function isSeededView (view) {
  return view instanceof SeededRoom || view instanceof WorkerSeededRoom
}

/**
 * A binary frame on a seeds socket.
 * @param {ArrayBuffer} frame @param {number} receivedAt ms
 * @param {object} room
 * @param {SeededRoom | WorkerSeededRoom} room.view
 * @param {import('./room-clock.js').RoomClock} room.clock
 * @param {(event: import('/protocol/drop-events-codec.js').DropEvent) => void} room.add puts a drop the view does not have yet on the board
 * @returns {{ check: DesyncCheck | Promise<DesyncCheck | null>, events: number, own: object[] } | null}
 *   the desync check (answered later when the room is simulated in the board worker;
 *   null there if the room was left meanwhile) and the page's own messages that rode in
 *   the frame (its `settled`), or null: not a drop-events frame (a seeds socket should get no other)
 */
export function applyDropEvents (frame, receivedAt, { view, clock, add }) {
  const batch = decodeDropEvents(frame)
  if (batch === null) return null
  clock.observe(batch.tick, receivedAt)
  // The batch may name drops the page has (its own `dropped`, `joined.balls`).
  for (const event of batch.events) if (!view.has(event.dropId)) add(event)
  return { check: view.check(batch.tick, batch.hash), events: batch.events.length, own: batch.own }
}

/** @typedef {{ ok: boolean, tick: number, server: string, local: string, balls: number }} DesyncCheck */

/**
 * A `pong` on a seeds socket: in a room it names the room's tick as the
 * server answered (server/realtime/connection.js), one more sample for the
 * room clock, which otherwise hears a tick only from `joined` and the
 * drop-events frames (none in a quiet room). A pong of another room (sent
 * before a join was answered) or without a tick changes nothing.
 * @param {{ room?: string, tick?: number }} pong @param {number} receivedAt ms
 * @param {{ room: string | null, clock: { observe: (tick: number, now: number) => void } | null }} joined
 *   the socket's room and its clock (a RoomClock: a snapshots room's timeline is fitted to its snapshots only)
 * @returns {boolean} whether the clock took it
 */
export function applyPong (pong, receivedAt, { room, clock }) {
  if (!(clock instanceof RoomClock) || room === null || pong.room !== room || !Number.isInteger(pong.tick)) return false
  clock.observe(pong.tick, receivedAt)
  return true
}

/**
 * Tells the server a room desynchronised on this page. Best effort: the
 * page has already switched the room to snapshots, and a report that
 * cannot be sent changes nothing for the player.
 * @param {{ room: string, tick: number, server: string, local: string, ballsInFlight: number, engineVersion: string }} desync
 * @param {string | null} token the session's
 */
export async function reportDesync (desync, token) {
  try {
    await apiRequest('POST', '/api/client-errors', {
      token,
      body: {
        code: 'E_DESYNC',
        message: `the page's flight hash at tick ${desync.tick} is ${desync.local}, the server's ${desync.server}`,
        room: desync.room,
        tick: desync.tick,
        serverHash: desync.server,
        localHash: desync.local,
        ballsInFlight: desync.ballsInFlight,
        engineVersion: desync.engineVersion,
        page: 'player'
      }
    })
    return true
  } catch {
    return false
  }
}
