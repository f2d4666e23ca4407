import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { DatabaseSync } from 'node:sqlite'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer } from '../server/helpers/server.js'

/**
 * Another process holds the SQLite ledger's write lock (issue #14, item 5):
 * no write waits for it on the event loop. Sessions, rotations and client
 * seeds wait on the writer thread while the rooms keep ticking, succeed once
 * the lock is free, and fail fast with 503 E_UNAVAILABLE (nothing changed)
 * if it stays held past SQLITE_BUSY_TIMEOUT_MS.
 */
const BUSY_TIMEOUT_MS = 600
const backend = storeBackend('sqlite')
let database
let server
let lock

beforeAll(async () => {
  await backend.setup()
  database = await backend.newDatabase()
  server = await startServer(database, { env: { SQLITE_BUSY_TIMEOUT_MS: String(BUSY_TIMEOUT_MS) }, tickRate: 60 })
})
afterAll(async () => {
  lock?.close()
  await server?.close()
  await backend.teardown()
})

/** A second connection, as another process would hold it: BEGIN IMMEDIATE takes the write lock. */
function holdWriteLock () {
  lock = new DatabaseSync(database.database.file)
  lock.exec('BEGIN IMMEDIATE')
  return () => { lock.exec('ROLLBACK'); lock.close(); lock = null }
}

/** The longest gap between two 10 ms timers while `work` runs: how long the event loop was held. */
async function longestStall (work) {
  let last = performance.now()
  let longest = 0
  const timer = setInterval(() => { const now = performance.now(); longest = Math.max(longest, now - last); last = now }, 10)
  try {
    return { result: await work(), longest }
  } finally {
    clearInterval(timer)
  }
}

describe('SQLite write lock held by another process', () => {
  it('never holds the event loop: writes wait on the writer thread and go through once the lock is free', async () => {
    const { token } = await server.player('8-low')
    const release = holdWriteLock()
    const ticksBefore = server.arena.scheduler.ticks
    const { result, longest } = await longestStall(async () => {
      const pending = [server.api('POST', '/api/session'), server.api('PUT', '/api/seeds/client', { token, body: { clientSeed: 'while-locked' } })]
      await new Promise((resolve) => setTimeout(resolve, BUSY_TIMEOUT_MS / 2))
      release()
      return Promise.all(pending)
    })
    expect(result.map((r) => r.status)).toEqual([201, 200])
    expect(longest).toBeLessThan(BUSY_TIMEOUT_MS / 2) // the game clock ran throughout (it stalled for the whole wait before)
    expect(server.arena.scheduler.ticks - ticksBefore).toBeGreaterThan(5)
  })

  it('fails fast with 503 E_UNAVAILABLE past the busy timeout, and changes nothing', async () => {
    const { token, session } = await server.player('8-low')
    const release = holdWriteLock()
    try {
      const { result, longest } = await longestStall(() => Promise.all([
        server.api('POST', '/api/session'),
        server.api('POST', '/api/seeds/rotate', { token }),
        server.api('PUT', '/api/seeds/client', { token, body: { clientSeed: 'never-written' } })
      ]))
      for (const response of result) {
        expect(response.status, response.text).toBe(503)
        expect(response.body.code).toBe('E_UNAVAILABLE')
      }
      expect(longest).toBeLessThan(BUSY_TIMEOUT_MS / 2)
    } finally {
      release()
    }
    const me = (await server.api('GET', '/api/me', { token })).body
    expect(me.serverSeedHash).toBe(session.serverSeedHash)
    expect(me.clientSeed).toBe(session.clientSeed)
    const [row] = await backend.query(database.database, 'SELECT client_seed FROM players WHERE id = $1', [session.playerId])
    expect(row.client_seed).toBe(session.clientSeed)
    // And everything works again once the lock is gone.
    expect((await server.api('POST', '/api/session')).status).toBe(201)
  })
})
