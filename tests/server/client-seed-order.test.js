import { describe, it, expect } from 'vitest'
import { STORE_KINDS } from './helpers/stores.js'
import { useServerOn } from './helpers/server.js'

/**
 * The client seed set over HTTP (PUT /api/seeds/client) and by a drop over
 * the WebSocket (`drop { clientSeed }`) race (issue #14, item 6): both paths
 * take effect in the order the server receives them, in memory and in the
 * ledger alike, so /api/me, the next drop and the stored seed always agree.
 */
describe.each(STORE_KINDS)('client seed changes on %s', (kind) => {
  const context = useServerOn(kind, { env: { DROP_RATE: '1000', DROP_BURST: '1000' } })

  it('land in one order for HTTP and WebSocket, in memory and in the ledger', async () => {
    const { server, backend, database } = context
    const { client, token, session } = await server.player('8-low')
    const trials = 25
    const winners = new Set()
    for (let i = 0; i < trials; i++) {
      // The PUT first, the drop a moment later, neither awaited before the other is sent.
      const put = server.api('PUT', '/api/seeds/client', { token, body: { clientSeed: `put-${i}` } })
      await new Promise((resolve) => setImmediate(resolve))
      client.send({ type: 'drop', bet: 1, clientSeed: `ws-${i}`, ref: `race-${i}` })
      const [reply, dropped] = await Promise.all([put, client.take((m) => m.type === 'dropped' && m.ref === `race-${i}`)])
      expect(reply.status).toBe(200)
      const me = (await server.api('GET', '/api/me', { token })).body
      const [row] = await backend.query(database.database, 'SELECT client_seed FROM players WHERE id = $1', [session.playerId])
      // Whichever the server took last holds everywhere: in memory, in the ledger, and for the next drop.
      client.send({ type: 'drop', bet: 1, ref: `after-${i}` })
      const next = await client.take((m) => m.type === 'dropped' && m.ref === `after-${i}`)
      expect([`put-${i}`, `ws-${i}`], `trial ${i}`).toContain(me.clientSeed)
      expect({ ledger: row.client_seed, nextDrop: next.clientSeed }, `trial ${i}: /api/me says ${me.clientSeed}`).toEqual({ ledger: me.clientSeed, nextDrop: me.clientSeed })
      expect(dropped.clientSeed).toBe(`ws-${i}`)
      winners.add(me.clientSeed.slice(0, 3))
    }
    // In order, each way round: the later one holds.
    await server.api('PUT', '/api/seeds/client', { token, body: { clientSeed: 'put-first' } })
    client.send({ type: 'drop', bet: 1, clientSeed: 'ws-last', ref: 'ws-last' })
    await client.take((m) => m.type === 'dropped' && m.ref === 'ws-last')
    expect((await server.api('GET', '/api/me', { token })).body.clientSeed).toBe('ws-last')
    // The drop first, then the PUT: the PUT holds.
    client.send({ type: 'drop', bet: 1, clientSeed: 'ws-first', ref: 'ws-first' })
    await client.take((m) => m.type === 'dropped' && m.ref === 'ws-first')
    const put = await server.api('PUT', '/api/seeds/client', { token, body: { clientSeed: 'put-last' } })
    expect(put.body.clientSeed).toBe('put-last')
    client.send({ type: 'drop', bet: 1, ref: 'final' })
    expect((await client.take((m) => m.type === 'dropped' && m.ref === 'final')).clientSeed).toBe('put-last')
    const [row] = await backend.query(database.database, 'SELECT client_seed FROM players WHERE id = $1', [session.playerId])
    expect(row.client_seed).toBe('put-last')
    expect((await server.api('GET', '/api/me', { token })).body.clientSeed).toBe('put-last')
  })
})
