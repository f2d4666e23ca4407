/**
 * Which rooms this process may run (after Colyseus's matchmaker driver:
 * one small interface, a local and a Redis implementation, chosen once at
 * start in modes.js). The arena never asks which one it has.
 *
 * - LocalRoomOwnership (local-room-ownership.js): one process owns its
 *   ledger, so every room is its own.
 * - ClusterRoomOwnership (../cluster/cluster-room-ownership.js): rooms are
 *   held by leases in Redis; a lost lease is reported (`onRoomLost`) and the
 *   arena evicts the room.
 *
 * It acts on nothing itself: it is handed the room registry (to read), the
 * group commit's queue (to release a lease behind the writes queued before)
 * and one callback.
 *
 * @typedef {object} RoomOwnership
 * @property {(services: OwnershipServices) => Promise<void>} start
 *   before the first tick: settles the drops a previous process left in flight (those it may)
 * @property {(roomId: string) => boolean} owns whether this process may run the room now
 * @property {(roomId: string) => Promise<void>} claim
 *   takes the room (settling what its last owner left), or throws E_WRONG_NODE / E_ROOM_MOVING
 * @property {(roomId: string) => void} disposed the arena let an idle room go
 * @property {() => Promise<object[]>} list every room running (anywhere), as GET /api/rooms shows it
 * @property {(url: string) => void} setListenUrl where this process listens, once it does
 * @property {() => Promise<void>} close after the arena has settled and committed everything
 *
 * @typedef {object} OwnershipServices
 * @property {{ get: (roomId: string) => ({ summary: () => object } | undefined), values: () => Iterable<{ summary: () => object }> }} rooms
 *   the rooms running here (rooms/room-registry.js)
 * @property {{ run: <T>(work: () => Promise<T>) => Promise<T> }} ledger the group commit's queue (game/drop.js)
 * @property {(roomId: string) => void} onRoomLost this process may no longer run the room (its lease went elsewhere)
 */
export {}
