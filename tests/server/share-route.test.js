import { describe, it, expect, beforeAll } from 'vitest'
import { sha256Hex } from '../../engine/index.js'
import { SHARE_TOKEN_LENGTH, shareTokenMessage, shareTokenOf } from '../../protocol/share-token.js'
import { shareToken } from '../../server/routes/share.js'
import { useServerOn } from './helpers/server.js'

/**
 * Another player's drop is served only to whoever has its seed: through
 * its share link GET /api/share/:id/:token, the token computed from the
 * drop seed (protocol/share-token.js) the same way by the server
 * (node:crypto) and the browser (WebCrypto). The unauthenticated
 * GET /api/public/drops/:id, which let anyone walk the ids, is gone: the
 * app's 404 like any unknown route.
 */
describe('share links', () => {
  const context = useServerOn('sqlite')
  let server
  /** A settled drop of a fresh player, as its `dropped` announced it. */
  let drop
  let other
  beforeAll(async () => {
    server = context.server
    const { client } = await server.player('8-low')
    const announced = []
    for (const ref of ['a', 'b']) {
      client.send({ type: 'drop', bet: 2, ref })
      const dropped = await client.take((m) => m.ref === ref)
      await client.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
      announced.push(dropped)
    }
    ;[drop, other] = announced
  })

  it('has one token rule: node:crypto on the server, WebCrypto as a page computes it, the same 20 hex digits', async () => {
    // Fixed vectors, computed apart (Python's hashlib): the first 20 hex digits of sha256("share:" + seed), UTF-8.
    expect(SHARE_TOKEN_LENGTH).toBe(20)
    for (const [seed, token] of [['0'.repeat(64), 'fe599e7880ddd3bf7ce5'], ['é ünïcode ✓', 'fb526ff8f808a5d449ef']]) {
      expect(shareTokenMessage(seed)).toBe(`share:${seed}`)
      expect(shareToken(seed)).toBe(token)
      expect(shareTokenOf(await sha256Hex(shareTokenMessage(seed)))).toBe(token)
    }
    for (const dropSeed of [drop.dropSeed, other.dropSeed]) {
      expect(shareToken(dropSeed)).toBe(shareTokenOf(await sha256Hex(shareTokenMessage(dropSeed))))
    }
  })

  it('serves a drop with the token of its seed, and refuses a wrong token, another drop\'s token and an unknown id alike', async () => {
    const right = await server.api('GET', `/api/share/${drop.dropId}/${shareToken(drop.dropSeed)}`)
    expect(right.status).toBe(200)
    expect(right.body).toMatchObject({ id: drop.dropId, dropSeed: drop.dropSeed, status: 'settled' })

    const unknown = await server.api('GET', `/api/share/999999/${shareToken(drop.dropSeed)}`)
    expect(unknown.status).toBe(404)
    const refusals = [
      `/api/share/${drop.dropId}/${'0'.repeat(SHARE_TOKEN_LENGTH)}`, // well formed, wrong
      `/api/share/${drop.dropId}/${shareToken(other.dropSeed)}`, // another drop's
      `/api/share/${other.dropId}/${shareToken(drop.dropSeed)}`, // and the other way round
      `/api/share/${drop.dropId}/${shareToken(drop.dropSeed.slice(1))}` // a seed one digit short
    ]
    for (const url of refusals) {
      const reply = await server.api('GET', url)
      expect(reply.status, url).toBe(404)
      // The same answer as no drop at all: a wrong token tells nothing about the id.
      expect({ code: reply.body.code, message: reply.body.message.replace(/\d+/, 'N') }, url)
        .toEqual({ code: unknown.body.code, message: unknown.body.message.replace(/\d+/, 'N') })
    }
    expect(unknown.body.code).toBe('E_NOT_FOUND')
    // Not a token at all (too short, not hex): refused by the schema before any lookup.
    for (const token of [shareToken(drop.dropSeed).slice(1), 'Z'.repeat(SHARE_TOKEN_LENGTH)]) {
      const reply = await server.api('GET', `/api/share/${drop.dropId}/${token}`)
      expect([reply.status, reply.body.code]).toEqual([400, 'E_BAD_REQUEST'])
    }
  })

  it('has no public drop route any more: the old path is the app\'s 404 E_NOT_FOUND, as an unknown route, and is not described', async () => {
    const unknownRoute = await server.api('GET', '/api/no-such-route')
    expect(unknownRoute.status).toBe(404)
    for (const url of [`/api/public/drops/${drop.dropId}`, `/api/public/drops/${other.dropId}`, '/api/public/drops/999999', '/api/public/drops/abc']) {
      const reply = await server.api('GET', url)
      expect(reply.status, url).toBe(404)
      expect(reply.body.code, url).toBe('E_NOT_FOUND')
      expect(Object.keys(reply.body).sort()).toEqual(Object.keys(unknownRoute.body).sort())
      // Nothing of the drop leaks in the answer.
      expect(reply.text).not.toContain(drop.dropSeed)
    }
    const openapi = (await server.api('GET', '/api/openapi.json')).body
    expect(Object.keys(openapi.paths).filter((path) => path.startsWith('/api/public'))).toEqual([])
    expect(openapi.paths['/api/share/{id}/{token}']).toBeDefined()
  })
})
