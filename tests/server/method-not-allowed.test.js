import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { fileURLToPath } from 'node:url'
import { buildApp } from '../../server/app.js'
import { loadConfig } from '../../server/config.js'
import { RouteMethods } from '../../server/routes/method-not-allowed.js'

const CLIENT_DIR = fileURLToPath(new URL('../../client/', import.meta.url))
/** Methods fastify routes; QUERY has a body, so a miss used to fail on its missing Content-Type first. */
const METHODS = ['GET', 'HEAD', 'POST', 'PUT', 'DELETE', 'PATCH', 'OPTIONS', 'TRACE', 'QUERY']

/**
 * A method a path does not have is 405 with an Allow header (RFC 9110
 * §15.5.6), for every path of the app (the client's catch-all included), as
 * the published description lists its methods; a path no route has is 404.
 */
describe('405 Method Not Allowed', () => {
  let app
  let openapi
  beforeAll(async () => {
    const config = loadConfig({ DATABASE_URL: 'sqlite::memory:', OPERATOR_TOKEN: 'operator-token-for-tests-0123456789', CLIENT_DIR, LOG_LEVEL: 'silent' })
    app = await buildApp(config, { logger: false })
    openapi = (await app.inject({ method: 'GET', url: '/api/openapi.json' })).json()
  })
  afterAll(() => app?.close())

  /** A concrete URL for a documented path. */
  const urlOf = (path) => path.replace('{id}', '1').replace('{*}', 'index.js')

  it('answers every method a documented path lacks with 405 and the methods it has, before reading any body', async () => {
    let refused = 0
    for (const [path, operations] of Object.entries(openapi.paths)) {
      const documented = Object.keys(operations).map((method) => method.toUpperCase())
      // fastify answers HEAD wherever there is a GET.
      const allowed = [...new Set([...documented, ...(documented.includes('GET') ? ['HEAD'] : [])])].sort()
      for (const method of METHODS.filter((m) => !allowed.includes(m))) {
        const response = await app.inject({ method, url: urlOf(path) })
        const where = `${method} ${path}`
        expect(response.statusCode, where).toBe(405)
        expect(response.headers.allow, where).toBe(allowed.join(', '))
        // A HEAD answer has no body (RFC 9110 §9.3.2).
        if (method === 'HEAD') expect(response.body, where).toBe('')
        else expect(response.json(), where).toEqual({ code: 'E_METHOD_NOT_ALLOWED', message: expect.stringContaining(method) })
        refused++
      }
    }
    expect(refused).toBeGreaterThan(100)
    // With a body of the wrong type too: the method is refused before the body is looked at.
    const withBody = await app.inject({ method: 'PUT', url: '/api/session', headers: { 'content-type': 'text/plain' }, payload: 'x' })
    expect([withBody.statusCode, withBody.headers.allow]).toEqual([405, 'POST'])
  })

  it('keeps 404 for a path no route has, and for a GET of a file the client does not have', async () => {
    for (const [method, url] of [['GET', '/api/no-such-route'], ['GET', '/no-such-file.js'], ['POST', '/api/no/such/route/either']]) {
      const response = await app.inject({ method, url })
      // POST /api/no/such/route/either: only the client's catch-all (GET, HEAD) matches it.
      if (method === 'POST') {
        expect([response.statusCode, response.headers.allow]).toEqual([405, 'GET, HEAD'])
        continue
      }
      expect(response.statusCode, url).toBe(404)
      expect(response.json().code).toBe('E_NOT_FOUND')
      expect(response.headers.allow).toBeUndefined()
    }
  })

  it('answers a GET that only the client\'s catch-all matched with the path\'s own methods', async () => {
    const response = await app.inject({ method: 'GET', url: '/api/session' })
    expect([response.statusCode, response.headers.allow]).toEqual([405, 'POST'])
  })
})

describe('RouteMethods', () => {
  it('takes the methods of the most specific pattern, as the router does', () => {
    const routes = new RouteMethods()
    routes.add('/*', ['GET', 'HEAD'])
    routes.add('/docs/static/*', ['GET'])
    routes.add('/api/drops/:id', ['GET', 'HEAD'])
    routes.add('/api/drops/latest', ['DELETE'])
    routes.add('/api/session', ['POST'])
    expect(routes.allowedFor('/api/session?x=1')).toEqual(['POST'])
    expect(routes.allowedFor('/api/drops/7')).toEqual(['GET', 'HEAD'])
    expect(routes.allowedFor('/api/drops/latest')).toEqual(['DELETE'])
    expect(routes.allowedFor('/docs/static/a/b.css')).toEqual(['GET'])
    expect(routes.allowedFor('/anything/else')).toEqual(['GET', 'HEAD'])
    // A parameter is one segment; a dot in a pattern is a dot.
    expect(routes.allowedFor('/api/drops/7/8')).toEqual(['GET', 'HEAD'])
    const noCatchAll = new RouteMethods()
    noCatchAll.add('/api/drops/:id', ['GET'])
    noCatchAll.add('/file.js', ['GET'])
    expect(noCatchAll.allowedFor('/api/drops/7/8')).toEqual([])
    expect(noCatchAll.allowedFor('/fileXjs')).toEqual([])
    expect(noCatchAll.allowedFor('/nothing')).toEqual([])
  })
})
