import { SqliteStore } from './sqlite-store.js'
import { PostgresStore } from './postgres-store.js'
import { checkDataDirectory } from './data-directory.js'

/**
 * Opens the ledger named by the configuration and brings its schema up to
 * date. Both stores implement the ledger contract (ledger-store.js),
 * so nothing above this line knows which one it has.
 * @param {import('../config.js').Config['database']} database
 * @returns {Promise<import('./ledger-store.js').LedgerStore>}
 */
export async function openStore (database) {
  if (database.kind === 'sqlite') checkDataDirectory(database.file)
  const store = database.kind === 'postgres'
    ? new PostgresStore({ url: database.url })
    : new SqliteStore({ file: database.file, busyTimeoutMs: database.busyTimeoutMs })
  try {
    await store.migrate()
  } catch (error) {
    await store.close().catch(() => {})
    throw error
  }
  return store
}
