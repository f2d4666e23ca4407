import { buildApp } from '../../../server/app.js'
import { loadConfig } from '../../../server/config.js'
import { openStore } from '../../../server/store/open-store.js'
import { beforeAll, afterAll } from 'vitest'
import { GameClient } from './game-client.js'
import { storeBackend } from './stores.js'
import { LIFTED_LIMITS } from '../../../tools/lifted-limits.js'

export const OPERATOR_TOKEN = 'operator-token-for-tests-0123456789'
/** Wall-clock ticks per second in tests: three times real time, same outcomes. */
export const TEST_TICK_RATE = 180

/**
 * A full server on a loopback port over `database`, with test-friendly
 * limits. `env` overrides configuration variables; `wrapStore` may wrap the
 * opened store (to inject failures). Silent, unless `logStream` is given:
 * then the server's JSON log lines (at LOG_LEVEL, `env`'s or info) go there.
 * @param {{ url: string }} database from storeBackend().newDatabase()
 * @param {{ env?: Record<string, string>, wrapStore?: (store: any) => any, tickRate?: number, logStream?: { write: (line: string) => void } }} [options]
 */
export async function startServer (database, { env = {}, wrapStore, tickRate = TEST_TICK_RATE, logStream } = {}) {
  const config = loadConfig({
    DATABASE_URL: database.url,
    OPERATOR_TOKEN,
    LOG_LEVEL: logStream ? 'info' : 'silent',
    ...LIFTED_LIMITS,
    JOIN_RATE: '1000',
    CLIENT_DIR: '/nonexistent/plinko-client',
    ...env
  })
  let store
  if (wrapStore) store = wrapStore(await openStore(config.database))
  const app = await buildApp(config, logStream ? { store, tickRate, logOutput: { stream: logStream } } : { store, tickRate, logger: false })
  await app.listen({ port: 0, host: '127.0.0.1' })
  const { port } = app.server.address()
  const clients = []
  return {
    app,
    config,
    arena: app.arena,
    port,
    /** app.inject with an optional bearer token; returns { status, body, headers, text }. */
    async api (method, url, { token, body } = {}) {
      const response = await app.inject({ method, url, payload: body, headers: token ? { authorization: `Bearer ${token}` } : {} })
      let json
      try { json = response.json() } catch {}
      return { status: response.statusCode, body: json, headers: response.headers, text: response.body }
    },
    /** A new guest session. */
    async session () {
      const response = await app.inject({ method: 'POST', url: '/api/session' })
      if (response.statusCode !== 201) throw new Error(`session: ${response.statusCode} ${response.body}`)
      return response.json()
    },
    wsUrl (token) {
      return `ws://127.0.0.1:${port}/ws${token === undefined ? '' : `?token=${token}`}`
    },
    /** A connected client (welcome received), closed with the server. */
    async connect (token) {
      const client = await GameClient.connect(this.wsUrl(token))
      clients.push(client)
      return client
    },
    /** A session plus a client that has joined `room` (with `delivery`, if given). */
    async player (room, { delivery } = {}) {
      const session = await this.session()
      const client = await this.connect(session.token)
      if (room) {
        client.send(delivery === undefined ? { type: 'join', room } : { type: 'join', room, delivery })
        client.joined = await client.take('joined')
      }
      return { session, client, token: session.token }
    },
    async close () {
      for (const client of clients) await client.close().catch(() => {})
      await app.close()
    }
  }
}

export { eventually } from '../../../tools/eventually.js'

/**
 * Registers hooks that give the enclosing describe block a fresh database
 * on store `kind` and a server over it; returns { backend, database, server },
 * filled in before the block's own beforeAll hooks run.
 * @param {string} kind one of STORE_KINDS
 * @param {Parameters<typeof startServer>[1]} [options]
 */
export function useServerOn (kind, options) {
  const context = { backend: storeBackend(kind), database: null, server: null }
  beforeAll(async () => {
    await context.backend.setup()
    context.database = await context.backend.newDatabase()
    context.server = await startServer(context.database, options)
  })
  afterAll(async () => {
    await context.server?.close()
    await context.backend.teardown()
  })
  return context
}
