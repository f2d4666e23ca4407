import { it } from 'vitest'
import { createHash } from 'node:crypto'
import { storeBackend } from './stores.js'
import { startRedis } from '../../../tools/redis-process.js'
import { SINGLE_PROCESS, CLUSTER } from '../../../server/coordination/modes.js'
import { toMilli } from '../../../server/game/money.js'

/**
 * The two modes' coordination (server/coordination/modes.js), for the
 * contract tests of its three interfaces: alone on a SQLite ledger, and as
 * processes of a cluster on a real PostgreSQL shared ledger and a real
 * Redis. `process()` opens one more process's store and coordination (for
 * the cluster: a second member on the same ledger and Redis); everything is
 * closed by teardown().
 */
export const MODES = [
  { name: 'single process', mode: SINGLE_PROCESS, backend: 'sqlite', redis: false },
  { name: 'cluster (Redis, shared PostgreSQL ledger)', mode: CLUSTER, backend: 'postgres', redis: true }
]

/**
 * `it` for a test that needs a second process (only a cluster has one), and
 * for the single-process mode nothing at all: such a test is not declared
 * rather than skipped, so every test a run reports was a test that ran.
 * @param {(typeof MODES)[number]} entry
 */
export function itWithOtherProcesses (entry) {
  return entry.redis ? it : () => {}
}

const silentLog = { info () {}, warn () {}, error () {}, debug () {}, child () { return silentLog } }

/** @param {(typeof MODES)[number]} entry */
export function coordinationTestbed ({ mode, backend: kind, redis: needsRedis }) {
  const backend = storeBackend(kind)
  let redis = null
  let database = null
  const opened = []
  let count = 0
  return {
    log: silentLog,
    async setup () {
      await backend.setup()
      if (needsRedis) redis = await startRedis()
      database = (await backend.newDatabase()).database
    },
    /** One process: its opened store and its coordination (not started). */
    async process ({ leaseTtlMs = 3000 } = {}) {
      const store = await mode.openStore(database)
      const config = { redisUrl: redis?.url ?? null, leaseTtlMs, publicUrl: `http://process-${++count}.test` }
      const coordination = mode.coordinate({ store, config, log: silentLog })
      const process = { store, config, ...coordination }
      opened.push(process)
      return process
    },
    redis: () => redis,
    async teardown () {
      for (const process of opened.splice(0).reverse()) {
        await process.close()
        await process.store.close()
      }
      await redis?.stop()
      await backend.teardown()
    }
  }
}

const sha256 = (text) => createHash('sha256').update(text).digest('hex')

/** A new player in the ledger, with its first server seed. */
export async function createPlayer (store, name, balance = 100) {
  const seed = { id: `seed-${name}-1`, seed: sha256(`server seed ${name}`), hash: sha256(sha256(`server seed ${name}`)) }
  const player = { id: `player-${name}`, tokenHash: sha256(`token ${name}`), balance: toMilli(balance), clientSeed: `client-${name}`, createdAt: Date.now(), seed }
  await store.createPlayer(player)
  return player.id
}

/** Calls `take` until it stops refusing with E_UNAVAILABLE (a cluster's next block is being reserved). */
export async function takeWhenReady (take) {
  for (;;) {
    try {
      return take()
    } catch (error) {
      if (error.code !== 'E_UNAVAILABLE') throw error
      await new Promise((resolve) => setImmediate(resolve))
    }
  }
}
