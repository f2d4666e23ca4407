import { openStore } from '../store/open-store.js'
import { openSharedLedger } from '../cluster/shared-ledger.js'
import { LocalRoomOwnership } from './local-room-ownership.js'
import { LocalSequences } from './local-sequences.js'
import { LocalAccountFeed } from './local-account-feed.js'
import { ClusterPresence } from '../cluster/cluster-presence.js'
import { ClusterRoomOwnership } from '../cluster/cluster-room-ownership.js'
import { ClusterSequences } from '../cluster/cluster-sequences.js'
import { ClusterAccountFeed } from '../cluster/cluster-account-feed.js'
import { localAddressLimits, redisAddressLimits } from '../limits/address-limits.js'

/**
 * The two ways the server runs, chosen once at start from the
 * configuration: alone on its own ledger (SQLite or PostgreSQL), or as one
 * process of a cluster (REDIS_URL) sharing a PostgreSQL ledger that decides
 * every balance, nonce and drop id. Each is a store, its coordination (room
 * ownership, sequences, the account feed: one small interface each, a local
 * and a cluster implementation) and where per-address limits are counted;
 * nothing else in the server differs.
 * @typedef {object} Mode
 * @property {string} name
 * @property {(database: import('../config.js').Config['database']) => Promise<any>} openStore opened and migrated
 * @property {(options: { store: any, config: import('../config.js').Config, log: import('pino').Logger }) => Coordination} coordinate
 * @property {(options: { config: import('../config.js').Config, log: import('pino').Logger }) => import('../limits/address-limits.js').AddressLimits} createAddressLimits
 */

/**
 * @typedef {object} Coordination this process's part in the mode, handed to the arena piece by piece
 * @property {import('./room-ownership.js').RoomOwnership} ownership which rooms it may run
 * @property {import('./sequences.js').Sequences} sequences where drop ids and nonces come from
 * @property {import('./account-feed.js').AccountFeed} feed notices of accounts changed elsewhere
 * @property {() => Promise<void>} close after the arena has settled and committed everything (never rejects)
 */

/** @type {Mode} */
export const SINGLE_PROCESS = {
  name: 'single process',
  openStore,
  coordinate: ({ store, log }) => {
    const ownership = new LocalRoomOwnership({ store, log })
    const feed = new LocalAccountFeed()
    const close = async () => {
      await ownership.close()
      await feed.close()
    }
    return { ownership, sequences: new LocalSequences({ store }), feed, close }
  },
  createAddressLimits: ({ config }) => localAddressLimits(config)
}

/** @type {Mode} */
export const CLUSTER = {
  name: 'cluster',
  openStore: openSharedLedger,
  coordinate: ({ store, config, log }) => {
    const presence = new ClusterPresence({ config, log })
    const ownership = new ClusterRoomOwnership({ presence, store, config, log })
    const feed = new ClusterAccountFeed({ presence, store, log })
    const close = async () => {
      await ownership.close()
      await feed.close()
      await presence.close()
    }
    return { ownership, sequences: new ClusterSequences({ store }), feed, close }
  },
  createAddressLimits: ({ config, log }) => redisAddressLimits(config, log)
}

/** @param {import('../config.js').Config} config @returns {Mode} */
export function modeOf (config) {
  return config.redisUrl ? CLUSTER : SINGLE_PROCESS
}
