import { describe, it, expect, beforeAll } from 'vitest'
import { ERROR_CODES } from '../../server/errors.js'
import { STORE_KINDS } from './helpers/stores.js'
import { useServerOn, startServer, OPERATOR_TOKEN } from './helpers/server.js'
import { GameClient } from './helpers/game-client.js'

/**
 * Every error code, provoked through the real protocol, and proof that a
 * refused request changes nothing: same balance, same next nonce, no new
 * ledger row. (E_SLOW_CONSUMER is covered in connection.test.js: loopback
 * sockets buffer megabytes before a server-side send queue grows.)
 */
describe.each(STORE_KINDS)('error codes on %s', (kind) => {
  const context = useServerOn(kind)
  const backend = context.backend
  const reached = new Set()
  let server
  let database
  beforeAll(() => { ({ server, database } = context) })

  /** Balance, next nonce and ledger rows of a player plus the whole ledger's size. */
  async function ledgerState (srv, db, token, playerId) {
    const me = await srv.api('GET', '/api/me', { token })
    const [mine] = await backend.query(db, 'SELECT COUNT(*) AS n FROM drops WHERE player_id = $1', [playerId])
    const [all] = await backend.query(db, 'SELECT COUNT(*) AS n, COALESCE(SUM(balance), 0) AS total FROM players')
    const [player] = await backend.query(db, 'SELECT balance FROM players WHERE id = $1', [playerId])
    return { balance: me.body.balance, nonce: me.body.nonce, storedBalance: Number(player.balance), drops: Number(mine.n), allDrops: Number(all.n), total: Number(all.total) }
  }

  function expectWsError (message, code) {
    expect(message).toMatchObject({ type: 'error', code })
    expect(typeof message.message).toBe('string')
    reached.add(code)
  }

  function expectHttpError (response, status, code) {
    expect(response.status).toBe(status)
    expect(response.body).toEqual({ code, message: expect.any(String) })
    reached.add(code)
  }

  it('refuses bad WebSocket messages and drops without touching the ledger', async () => {
    const { session, client, token } = await server.player()
    const before = await ledgerState(server, database.database, token, session.playerId)

    expectWsError(await client.expectError('{not json'), 'E_BAD_MESSAGE')
    expectWsError(await client.expectError('[1, 2]'), 'E_BAD_MESSAGE')
    expectWsError(await client.expectError({ type: 'join' }), 'E_BAD_MESSAGE')
    expectWsError(await client.expectError({ type: 'ping', extra: true }), 'E_BAD_MESSAGE')
    client.socket.send(Buffer.from([1, 2, 3]), { binary: true })
    expectWsError(await client.take('error'), 'E_BAD_MESSAGE')
    expectWsError(await client.expectError({ type: 'teleport', ref: 'r1' }), 'E_UNKNOWN_TYPE')
    expect(client.messages.at(-1).ref).toBe('r1')

    expectWsError(await client.expectError({ type: 'drop', bet: 10, ref: 9 }), 'E_NOT_IN_ROOM')
    expect(client.messages.at(-1).ref).toBe(9)
    expectWsError(await client.expectError({ type: 'leave' }), 'E_NOT_IN_ROOM')
    expectWsError(await client.expectError({ type: 'join', room: '17-medium' }), 'E_UNKNOWN_ROOM')
    expectWsError(await client.expectError({ type: 'join', room: 'lobby' }), 'E_UNKNOWN_ROOM')
    const badDelivery = await client.expectError({ type: 'join', room: '13-low', delivery: 'positions', ref: 'd1' })
    expectWsError(badDelivery, 'E_BAD_DELIVERY')
    expect(badDelivery.ref).toBe('d1')

    client.send({ type: 'join', room: '13-low' })
    await client.take('joined')
    for (const bet of [0, -5, 1.5, '10', 1000001, null]) {
      expectWsError(await client.expectError({ type: 'drop', bet }), 'E_BAD_BET')
    }
    for (const clientSeed of ['', 'x'.repeat(65), 'tab\there', 'é']) {
      expectWsError(await client.expectError({ type: 'drop', bet: 10, clientSeed }), 'E_BAD_SEED')
    }
    expectWsError(await client.expectError({ type: 'drop', bet: 100001 }), 'E_INSUFFICIENT_FUNDS')
    // The token bucket (20 drops, 20/s) refuses a burst even of refused drops.
    for (let i = 0; i < 30; i++) client.send({ type: 'drop', bet: 200000 })
    await client.sync()
    const burst = client.messages.filter((m) => m.type === 'error').slice(-30).map((m) => m.code)
    expect(burst).toContain('E_RATE_LIMITED')
    expect(burst.filter((code) => code === 'E_INSUFFICIENT_FUNDS').length).toBeLessThanOrEqual(20)
    reached.add('E_RATE_LIMITED')

    // Nothing was debited, no nonce was used, nothing was recorded; the connection is still up.
    expect(await ledgerState(server, database.database, token, session.playerId)).toEqual(before)
    expect(client.messages.filter((m) => m.type === 'dropped')).toEqual([])
    expect(client.closeEvent).toBeNull()
    await client.sync()
    await client.close()
  })

  it('closes unauthenticated WebSockets with 4401 and oversized frames with 1009', async () => {
    for (const url of [server.wsUrl(), server.wsUrl('f'.repeat(64)), server.wsUrl('nonsense')]) {
      const client = new GameClient(url)
      const error = await client.take('error')
      expect(error.code).toBe('E_UNAUTHORIZED')
      expect((await client.closed).code).toBe(4401)
    }
    reached.add('E_UNAUTHORIZED')

    const { client } = await server.player()
    client.send({ type: 'ping', ref: 'x'.repeat(5000) })
    expect((await client.closed).code).toBe(1009)
  })

  it('answers bad HTTP requests with named 4xx codes', async () => {
    const alice = await server.player('13-medium')
    const bob = await server.session()
    alice.client.send({ type: 'drop', bet: 1 })
    const dropped = await alice.client.take('dropped')
    await alice.client.take('settled')
    const before = await ledgerState(server, database.database, alice.token, alice.session.playerId)

    expectHttpError(await server.api('GET', '/api/me'), 401, 'E_UNAUTHORIZED')
    expectHttpError(await server.api('GET', '/api/me', { token: 'a'.repeat(64) }), 401, 'E_UNAUTHORIZED')
    expectHttpError(await server.api('POST', '/api/seeds/rotate'), 401, 'E_UNAUTHORIZED')
    // Someone else's drop answers as no drop would: ids cannot be counted.
    const othersDrop = await server.api('GET', `/api/drops/${dropped.dropId}`, { token: bob.token })
    expectHttpError(othersDrop, 404, 'E_NOT_FOUND')
    expect(othersDrop.body.message).toBe(`you have no drop ${dropped.dropId}`)
    expect((await server.api('GET', `/api/drops/${dropped.dropId + 1000}`, { token: bob.token })).body.message).toBe(`you have no drop ${dropped.dropId + 1000}`)
    expectHttpError(await server.api('GET', '/api/drops/987654321', { token: alice.token }), 404, 'E_NOT_FOUND')
    expectHttpError(await server.api('GET', '/api/audit/drops', { token: 'not-the-operator-token' }), 403, 'E_FORBIDDEN')
    expectHttpError(await server.api('GET', '/api/no-such-route'), 404, 'E_NOT_FOUND')
    expectHttpError(await server.api('DELETE', '/api/me', { token: alice.token }), 405, 'E_METHOD_NOT_ALLOWED')
    expectHttpError(await server.api('GET', '/api/drops?limit=0', { token: alice.token }), 400, 'E_BAD_REQUEST')
    expectHttpError(await server.api('GET', '/api/drops/abc', { token: alice.token }), 400, 'E_BAD_REQUEST')
    expectHttpError(await server.api('PUT', '/api/seeds/client', { token: alice.token, body: { clientSeed: 'ok', extra: 1 } }), 400, 'E_BAD_REQUEST')
    expectHttpError(await server.api('PUT', '/api/seeds/client', { token: alice.token, body: { clientSeed: '' } }), 400, 'E_BAD_SEED')
    expectHttpError(await server.api('PUT', '/api/seeds/client', { token: alice.token, body: { clientSeed: 'x'.repeat(65) } }), 400, 'E_BAD_SEED')
    expectHttpError(await server.api('GET', '/api/audit/rooms/99-low/stats', { token: OPERATOR_TOKEN }), 404, 'E_UNKNOWN_ROOM')
    expectHttpError(await server.api('GET', '/api/audit/rooms/8-low/stats?engineVersion=0.0.9', { token: OPERATOR_TOKEN }), 400, 'E_UNKNOWN_ENGINE_VERSION')
    expectHttpError(await server.api('GET', '/api/audit/verify?serverSeed=s&clientSeed=c&nonce=1&engineVersion=latest', { token: OPERATOR_TOKEN }), 400, 'E_UNKNOWN_ENGINE_VERSION')
    expectHttpError(await server.api('GET', '/api/audit/export', { token: OPERATOR_TOKEN }), 400, 'E_BAD_REQUEST')
    expectHttpError(await server.api('GET', '/api/audit/drops?from=yesterday', { token: OPERATOR_TOKEN }), 400, 'E_BAD_REQUEST')
    const badJson = await server.app.inject({ method: 'PUT', url: '/api/seeds/client', headers: { authorization: `Bearer ${alice.token}`, 'content-type': 'application/json' }, payload: '{"clientSeed":' })
    expect(badJson.statusCode).toBe(400)
    expect(badJson.json().code).toBe('E_BAD_REQUEST')

    expect(await ledgerState(server, database.database, alice.token, alice.session.playerId)).toEqual(before)
    await alice.client.close()
  })

  it('limits new sessions per IP, caps balls per room, refuses work while shutting down and refunds a failed commit', async () => {
    const db = await backend.newDatabase()
    let failNextCommit = false
    const special = await startServer(db, {
      env: { SESSION_RATE_LIMIT: '3', MAX_BALLS_PER_ROOM: '1' },
      wrapStore: (store) => new Proxy(store, {
        get (target, property) {
          if (property === 'commitBatch') {
            return async (batch) => {
              if (failNextCommit && batch.drops.length > 0) {
                failNextCommit = false
                throw new Error('injected commit failure')
              }
              return target.commitBatch(batch)
            }
          }
          const value = target[property]
          return typeof value === 'function' ? value.bind(target) : value
        }
      })
    })
    try {
      const { session, client, token } = await special.player('8-high')
      await special.session()
      await special.session()
      expectHttpError(await special.api('POST', '/api/session'), 429, 'E_RATE_LIMITED')

      // A failed group commit: the drop is refused as E_INTERNAL, nothing is debited or announced.
      const before = await ledgerState(special, db.database, token, session.playerId)
      failNextCommit = true
      client.send({ type: 'drop', bet: 50, ref: 'doomed' })
      const internal = await client.take('error')
      expectWsError(internal, 'E_INTERNAL')
      expect(internal.ref).toBe('doomed')
      const after = await ledgerState(special, db.database, token, session.playerId)
      // The nonce it took is burnt (never reused), everything else is as before.
      expect(after).toEqual({ ...before, nonce: before.nonce + 1 })
      expect(client.messages.filter((m) => m.type === 'dropped')).toEqual([])

      // One ball per room here: a second drop while the first is in flight is refused.
      client.send({ type: 'drop', bet: 7 })
      client.send({ type: 'drop', bet: 7 })
      expectWsError(await client.take('error'), 'E_ROOM_FULL')
      const dropped = await client.take('dropped')
      expect(dropped.nonce).toBe(before.nonce + 1)
      const settled = await client.take('settled')
      expect(settled.balance).toBe(before.balance - 7 + settled.payout)
      const [count] = await backend.query(db.database, 'SELECT COUNT(*) AS n FROM drops WHERE player_id = $1', [session.playerId])
      expect(Number(count.n)).toBe(1)

      special.arena.stopAccepting()
      const beforeShutdown = await ledgerState(special, db.database, token, session.playerId)
      expectWsError(await client.expectError({ type: 'drop', bet: 1 }), 'E_UNAVAILABLE')
      expectWsError(await client.expectError({ type: 'join', room: '9-high' }), 'E_UNAVAILABLE')
      expect(await ledgerState(special, db.database, token, session.playerId)).toEqual(beforeShutdown)
    } finally {
      await special.close()
    }
  })

  it('reached every error code except E_SLOW_CONSUMER (see connection.test.js) and the cluster ones (tests/cluster)', () => {
    const clusterOnly = ['E_WRONG_NODE', 'E_ROOM_MOVING', 'E_SEED_ROTATED']
    const hardeningOnly = [
      'E_TOO_MANY_CONNECTIONS', // tests/hardening/abuse.test.js
      'E_SEED_ROTATING', // tests/server/seed-rotation-order.test.js (a rotation slowed so drops meet it)
      'E_HEADERS_TOO_LARGE', 'E_TIMEOUT', 'E_PAYLOAD_TOO_LARGE', 'E_UNSUPPORTED_MEDIA_TYPE' // tests/hardening/http-client-errors.test.js (raw sockets)
    ]
    const expected = Object.keys(ERROR_CODES).filter((code) => code !== 'E_SLOW_CONSUMER' && !clusterOnly.includes(code) && !hardeningOnly.includes(code))
    expect([...reached].sort()).toEqual(expected.sort())
  })
})
