import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { STORE_KINDS, storeBackend } from './helpers/stores.js'
import { startServer } from './helpers/server.js'

/**
 * A rotation and a burst of drops from the same player at once: no drop
 * may be recorded on a seed after its `revealed_at` (an auditor reads that
 * as a drop on a seed already public). The rotation's write is slowed to
 * 100 ms (a busy disk) so that the burst lands while it is being written;
 * before, every drop accepted meanwhile was recorded on the old seed after
 * its reveal.
 */
const ROTATION_WRITE_MS = 100
const DROPS = 40

describe.each(STORE_KINDS)('seed rotation and drops on %s', (kind) => {
  const backend = storeBackend(kind)
  let server
  let database
  let rotationStarted
  beforeAll(async () => {
    await backend.setup()
    database = await backend.newDatabase()
    server = await startServer(database, {
      env: { DROP_RATE: '1000', DROP_BURST: '1000' },
      wrapStore: (store) => new Proxy(store, {
        get (target, property) {
          if (property === 'rotateSeed') {
            return async (rotation) => {
              rotationStarted?.()
              await new Promise((resolve) => setTimeout(resolve, ROTATION_WRITE_MS))
              return target.rotateSeed(rotation)
            }
          }
          const value = Reflect.get(target, property)
          return typeof value === 'function' ? value.bind(target) : value
        }
      })
    })
  })
  afterAll(async () => {
    await server?.close()
    await backend.teardown()
  })

  it('records no drop on a seed after its revealed_at, and refuses (debits nothing for) drops sent during the rotation', async () => {
    const { client, token, session } = await server.player('8-low')
    const started = new Promise((resolve) => { rotationStarted = resolve })
    const rotation = server.api('POST', '/api/seeds/rotate', { token })
    await started
    for (let i = 0; i < DROPS; i++) client.send({ type: 'drop', bet: 1, ref: `d${i}` })
    const rotated = await rotation
    expect(rotated.status).toBe(200)
    const replies = []
    for (let i = 0; i < DROPS; i++) replies.push(await client.take((m) => m.ref === `d${i}`))
    const late = await backend.query(database.database, `SELECT d.id FROM drops d JOIN server_seeds s ON s.id = d.server_seed_id
      WHERE s.revealed_at IS NOT NULL AND d.created_at > s.revealed_at`)
    expect(late, 'drops recorded on the old seed after its revealed_at').toEqual([])
    const refused = replies.filter((m) => m.type === 'error')
    for (const reply of refused) expect(reply.code).toBe('E_SEED_ROTATING')
    for (const reply of replies.filter((m) => m.type === 'dropped')) expect(reply.serverSeedHash).toBe(rotated.body.serverSeedHash)
    // After the answer, drops go through on the new seed.
    client.send({ type: 'drop', bet: 1, ref: 'after' })
    expect(await client.take((m) => m.ref === 'after')).toMatchObject({ type: 'dropped', serverSeedHash: rotated.body.serverSeedHash })

    const [{ n }] = await backend.query(database.database, 'SELECT COUNT(*) AS n FROM drops WHERE player_id = $1', [session.playerId])
    console.info(`[seed-rotation-order] ${kind}: ${DROPS} drops sent during a ${ROTATION_WRITE_MS} ms rotation write: ${refused.length} refused (E_SEED_ROTATING), ${late.length} recorded after revealed_at`)
    expect(Number(n)).toBe(DROPS - refused.length + 1)
    await client.close()
  })
})
