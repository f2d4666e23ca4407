/**
 * What the arena asks of whoever coordinates it with other processes
 * (after Colyseus's presence, which is always installed: `LocalPresence`
 * when alone). Chosen once at start (modes.js); the arena and the drop
 * lifecycle never ask which one they have.
 *
 * - LocalCoordinator (local-coordinator.js): one process owns the ledger;
 *   every room is ours, nonces and drop ids are counted in memory.
 * - ClusterCoordinator (../cluster/cluster-coordinator.js): rooms are held
 *   by leases in Redis, nonces and drop ids come in blocks from the shared
 *   ledger, committed balances and seed rotations are announced to the other processes, and a
 *   lost lease evicts the room (Arena.evictRoom).
 *
 * @typedef {object} Coordinator
 * @property {(arena: import('../arena.js').Arena) => Promise<void>} start
 *   before the first tick: settles the drops a previous process left in flight (those it may)
 * @property {(roomId: string) => boolean} ownsRoom whether this process may run the room now
 * @property {(roomId: string) => Promise<void>} claimRoom
 *   takes the room (settling what its last owner left), or throws E_WRONG_NODE / E_ROOM_MOVING
 * @property {(roomId: string) => void} roomDisposed the arena let an idle room go
 * @property {(seed: { id: string, nextNonce: number }) => number} takeNonce the seed's next nonce, never given back
 * @property {() => number} takeDropId the next drop id, never given back
 * @property {(playerIds: Iterable<string>) => void} balancesCommitted these players' balances changed in the ledger
 * @property {(account: import('../game/accounts.js').Account) => Promise<void>} seedRotated
 *   this process rotated the account's server seed (committed): resolves once every other process holding it uses the new one
 * @property {(account: import('../game/accounts.js').Account) => Promise<void>} seedOutdated
 *   the ledger refused a drop on a seed no longer active (E_SEED_ROTATED): re-reads the account's active seed (never rejects)
 * @property {() => Promise<object[]>} listRooms every room running (anywhere), as GET /api/rooms shows it
 * @property {(url: string) => void} setListenUrl where this process listens, once it does
 * @property {() => Promise<void>} close after the arena has settled and committed everything
 */
export {}
