import { openStore } from '../store/open-store.js'
import { openSharedLedger } from '../cluster/shared-ledger.js'
import { LocalCoordinator } from './local-coordinator.js'
import { ClusterCoordinator } from '../cluster/cluster-coordinator.js'
import { localAddressLimits, redisAddressLimits } from '../limits/address-limits.js'

/**
 * The two ways the server runs, chosen once at start from the
 * configuration: alone on its own ledger (SQLite or PostgreSQL), or as one
 * process of a cluster (REDIS_URL) sharing a PostgreSQL ledger that decides
 * every balance, nonce and drop id. Each is a store, a coordinator and
 * where per-address limits are counted; nothing else in the server differs.
 * @typedef {object} Mode
 * @property {string} name
 * @property {(database: import('../config.js').Config['database']) => Promise<any>} openStore opened and migrated
 * @property {(options: { store: any, config: import('../config.js').Config, log: import('pino').Logger }) => import('./coordinator.js').Coordinator} createCoordinator
 * @property {(options: { config: import('../config.js').Config, log: import('pino').Logger }) => import('../limits/address-limits.js').AddressLimits} createAddressLimits
 */

/** @type {Mode} */
export const SINGLE_PROCESS = {
  name: 'single process',
  openStore,
  createCoordinator: ({ store, log }) => new LocalCoordinator({ store, log }),
  createAddressLimits: ({ config }) => localAddressLimits(config)
}

/** @type {Mode} */
export const CLUSTER = {
  name: 'cluster',
  openStore: openSharedLedger,
  createCoordinator: ({ store, config, log }) => new ClusterCoordinator({ store, config, log }),
  createAddressLimits: ({ config, log }) => redisAddressLimits(config, log)
}

/** @param {import('../config.js').Config} config @returns {Mode} */
export function modeOf (config) {
  return config.redisUrl ? CLUSTER : SINGLE_PROCESS
}
