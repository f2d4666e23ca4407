import { copyFileSync, mkdtempSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { buildApp } from '../../../server/app.js'
import { loadConfig } from '../../../server/config.js'
import { LIFTED_LIMITS } from '../../../tools/lifted-limits.js'

export const OPERATOR_TOKEN = 'operator-token-for-e2e-tests-0123456789'
export const CLIENT_DIR = fileURLToPath(new URL('../../../client/', import.meta.url))

/**
 * The real server, in this process, on a loopback port, serving client/
 * over a throwaway SQLite file, with a known operator token. restart()
 * closes it (gracefully: balls in flight are settled) and starts a new
 * one on the same port over the same file, as a deploy would.
 * @param {{ tickRate?: number, env?: Record<string, string>, ledger?: string }} [options]
 *   tickRate: wall-clock ticks per second (60 is real time; outcomes do not depend on it);
 *   ledger: a SQLite file to start from (copied), e.g. a fixture recorded by an older version
 */
export async function startArenaServer ({ tickRate = 60, env = {}, ledger } = {}) {
  const dir = mkdtempSync(join(tmpdir(), 'plinko-e2e-db-'))
  const file = join(dir, 'plinko.sqlite')
  if (ledger) copyFileSync(ledger, file)
  const config = loadConfig({
    DATABASE_URL: `sqlite:${file}`,
    OPERATOR_TOKEN,
    LOG_LEVEL: 'silent',
    CLIENT_DIR,
    ...LIFTED_LIMITS,
    ...env
  })
  let app = await buildApp(config, { tickRate, logger: false })
  await app.listen({ port: 0, host: '127.0.0.1' })
  const port = app.server.address().port

  const server = {
    config,
    port,
    base: `http://127.0.0.1:${port}`,
    get app () { return app },
    get arena () { return app.arena },
    /** GET/POST… through app.inject; `token` goes in Authorization: Bearer. */
    async api (method, url, { token, body } = {}) {
      const response = await app.inject({ method, url, payload: body, headers: token ? { authorization: `Bearer ${token}` } : {} })
      let json
      try { json = response.json() } catch {}
      return { status: response.statusCode, body: json, headers: response.headers, text: response.body }
    },
    /** An operator API call; throws unless 200. */
    async audit (url) {
      const response = await server.api('GET', url, { token: OPERATOR_TOKEN })
      if (response.status !== 200) throw new Error(`${url}: ${response.status} ${response.text}`)
      return response.body
    },
    wsUrl (token) {
      return `ws://127.0.0.1:${port}/ws?token=${token}`
    },
    /** Ends every WebSocket abruptly (no close frame), as a network failure would. */
    dropConnections () {
      let dropped = 0
      for (const connection of app.arena.connections) {
        connection.socket.terminate()
        dropped++
      }
      return dropped
    },
    /**
     * Stops the server; start() brings it back on the same port and file.
     * `down` runs while it is down.
     */
    async restart (down = async () => {}) {
      await app.close()
      await down()
      app = await buildApp(config, { tickRate, logger: false })
      await app.listen({ port, host: '127.0.0.1' })
    },
    async close () {
      await app.close().catch(() => {})
      rmSync(dir, { recursive: true, force: true })
    }
  }
  return server
}
