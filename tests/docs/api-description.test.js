import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import diagnostics from 'node:diagnostics_channel'
import { fileURLToPath } from 'node:url'
import Ajv from 'ajv'
import { Validator } from '@seriousme/openapi-schema-validator'
import asyncApiSpecs from '@asyncapi/specs'
import fc from 'fast-check'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer, OPERATOR_TOKEN } from '../server/helpers/server.js'
import { ERROR_CODES } from '../../server/errors.js'
import { WEBSOCKET_ONLY_CODES } from '../../server/routes/api-docs.js'
import { clientMessageSchemas } from '../../protocol/client-messages.js'
import { ENGINE_VERSIONS } from '../../engine/version.js'

const CLIENT_DIR = fileURLToPath(new URL('../../client/', import.meta.url))

/**
 * The description the server publishes (/api/openapi.json, /api/asyncapi.json)
 * against the app itself: every route the app registers (seen through an
 * onRoute hook on the real app) is documented and nothing else is; the
 * document is valid OpenAPI (a real validator, not a shape check); its
 * security and error responses say what the routes really do.
 */
describe('the API description', () => {
  const backend = storeBackend('sqlite')
  /** Every route the app registers, as `METHOD url`, from an onRoute hook added when the app is created. */
  const registered = []
  let server
  let openapi
  let session

  beforeAll(async () => {
    // fastify publishes each new instance on this channel before any plugin is registered.
    const watch = ({ fastify }) => fastify.addHook('onRoute', (route) => {
      for (const method of [route.method].flat()) registered.push(`${method} ${route.url}`)
    })
    diagnostics.subscribe('fastify.initialization', watch)
    try {
      await backend.setup()
      server = await startServer(await backend.newDatabase(), { env: { CLIENT_DIR } })
    } finally {
      diagnostics.unsubscribe('fastify.initialization', watch)
    }
    const response = await server.api('GET', '/api/openapi.json')
    expect(response.status).toBe(200)
    openapi = response.body
    session = await server.session()
  })
  afterAll(async () => {
    await server?.close()
    await backend.teardown()
  })

  /** `METHOD /path` of every documented operation, in fastify's spelling (`{id}` → `:id`, `{*}` → `*`). */
  const documented = () => Object.entries(openapi.paths).flatMap(([path, methods]) =>
    Object.keys(methods).map((method) => `${method.toUpperCase()} ${path.replace(/\{\*\}/g, '*').replace(/\{(\w+)\}/g, ':$1')}`))

  it('is valid OpenAPI 3.1', async () => {
    const validator = new Validator()
    const result = await validator.validate(structuredClone(openapi))
    expect(result.errors ?? []).toEqual([])
    expect(result.valid).toBe(true)
    expect(validator.version).toBe('3.1')
    // The validator does check: a response without its description is refused.
    const broken = structuredClone(openapi)
    delete broken.paths['/api/health'].get.responses['200'].description
    expect((await new Validator().validate(broken)).valid).toBe(false)
  })

  it('lists every route the app registers, and only those', () => {
    expect(registered.length).toBeGreaterThan(20)
    // HEAD comes with every GET (fastify's exposeHeadRoutes); Swagger UI's own assets and the
    // JSON and YAML copies of the document are the only routes left out on purpose.
    const undocumented = new Set(['GET /docs/static/index.html', 'GET /docs/static/swagger-initializer.js', 'GET /docs/static/*', 'GET /docs/json', 'GET /docs/yaml'])
    const expected = [...new Set(registered.filter((route) => !route.startsWith('HEAD ') && !undocumented.has(route)))].sort()
    const listed = [...new Set(documented().filter((route) => !route.startsWith('HEAD ')))].sort()
    expect(listed).toEqual(expected)
    for (const route of undocumented) expect(registered, `${route} is still registered`).toContain(route)
  })

  /** A URL for a documented path: path parameters filled in with something the route accepts. */
  const urlOf = (path) => path.replace('{id}', '1').replace('{*}', 'index.js').replace('/api/audit/rooms/1', '/api/audit/rooms/16-medium')

  it('names the security each route really checks: without a token, exactly the documented ones answer 401', async () => {
    const schemes = Object.keys(openapi.components.securitySchemes).sort()
    expect(schemes).toEqual(['operatorToken', 'playerToken'])
    let secured = 0
    let optional = 0
    for (const [path, methods] of Object.entries(openapi.paths)) {
      for (const [method, operation] of Object.entries(methods)) {
        if (method === 'head') continue
        const response = await server.api(method.toUpperCase(), urlOf(path))
        const where = `${method.toUpperCase()} ${path}`
        // An empty requirement among them ({}): the token is optional (the operator token check answers 200 either way).
        if (operation.security?.some((requirement) => Object.keys(requirement).length === 0)) {
          optional++
          expect(response.status, where).toBe(200)
          expect((await server.api(method.toUpperCase(), urlOf(path), { token: session.token })).status, where).toBe(200)
          expect(operation.responses['401'], where).toBeUndefined()
          expect(operation.responses['403'], where).toBeUndefined()
        } else if (operation.security) {
          secured++
          expect(response.status, where).toBe(401)
          expect(response.body, where).toEqual({ code: 'E_UNAUTHORIZED', message: expect.any(String) })
          expect(operation.responses['401'], where).toBeDefined()
          // A player's token is not the operator's: 403, as documented.
          if (operation.security[0].operatorToken) {
            expect((await server.api(method.toUpperCase(), urlOf(path), { token: session.token })).status, where).toBe(403)
            expect(operation.responses['403'], where).toBeDefined()
          }
        } else {
          expect(response.status, where).not.toBe(401)
        }
      }
    }
    expect(secured).toBeGreaterThanOrEqual(11)
    expect(optional).toBe(1)
  })

  it('documents errors as { code, message } with the HTTP codes of each status, from ERROR_CODES', () => {
    let errorResponses = 0
    for (const [path, methods] of Object.entries(openapi.paths)) {
      for (const [method, operation] of Object.entries(methods)) {
        for (const [status, response] of Object.entries(operation.responses)) {
          if (Number(status) < 400) continue
          errorResponses++
          const where = `${method.toUpperCase()} ${path} ${status}`
          const schema = response.content['application/json'].schema
          expect(schema.required, where).toEqual(['code', 'message'])
          const codes = Object.entries(ERROR_CODES).filter(([code, known]) => known.status === Number(status) && !WEBSOCKET_ONLY_CODES.includes(code)).map(([code]) => code)
          expect(schema.properties.code.enum, where).toEqual(codes)
          for (const code of codes) expect(response.description, where).toContain(code)
        }
      }
    }
    expect(errorResponses).toBeGreaterThan(30)
    // The Error schema names every code the server has, with its message.
    expect(openapi.components.schemas.Error.properties.code.enum).toEqual(Object.keys(ERROR_CODES))
  })

  it('describes the answers the routes really give: status documented, JSON body matching its schema', async () => {
    const ajv = new Ajv({ strict: false, allErrors: true })
    const tokens = { playerToken: session.token, operatorToken: OPERATOR_TOKEN }
    let checked = 0
    for (const [path, methods] of Object.entries(openapi.paths)) {
      for (const [method, operation] of Object.entries(methods)) {
        if (method === 'head' || path === '/ws') continue
        const scheme = operation.security ? Object.keys(operation.security[0])[0] : null
        const response = await server.api(method.toUpperCase(), urlOf(path), { token: scheme ? tokens[scheme] : undefined, body: operation.requestBody ? {} : undefined })
        const where = `${method.toUpperCase()} ${path} → ${response.status} ${response.text.slice(0, 120)}`
        const documentedResponse = operation.responses[String(response.status)]
        expect(documentedResponse, where).toBeDefined()
        const schema = documentedResponse.content?.['application/json']?.schema
        if (schema && response.headers['content-type']?.startsWith('application/json')) {
          const validate = ajv.compile(schema)
          expect(validate(response.body), `${where}: ${ajv.errorsText(validate.errors)}`).toBe(true)
          checked++
        }
      }
    }
    expect(checked).toBeGreaterThanOrEqual(15)
  })

  it('describes the audit routes\' inputs as the server takes them: times, engine versions, one history per export', async () => {
    const operator = { token: OPERATOR_TOKEN }
    const query = (path) => Object.fromEntries(openapi.paths[path].get.parameters.filter((p) => p.in === 'query').map((p) => [p.name, p]))
    // Time filters: every string the pattern allows is a time the server takes; outside it, refused.
    const { from } = query('/api/audit/drops')
    const pattern = new RegExp(from.schema.pattern, 'u')
    await fc.assert(fc.asyncProperty(fc.stringMatching(pattern), async (time) => {
      const response = await server.api('GET', `/api/audit/drops?from=${encodeURIComponent(time)}&to=${encodeURIComponent(time)}`, operator)
      expect(response.status, `from=${time}: ${response.text}`).toBe(200)
    }), { numRuns: 200 })
    for (const time of ['', 'yesterday', '1e5', '2026-13-01']) {
      expect(pattern.test(time), time).toBe(false)
      expect((await server.api('GET', `/api/audit/drops?from=${encodeURIComponent(time)}`, operator)).status, time).toBe(400)
    }
    // Engine versions: the shipped ones (engine/version.js), a closed set.
    for (const path of ['/api/audit/verify', '/api/audit/rooms/{id}/stats']) expect(query(path).engineVersion.schema.enum, path).toEqual(ENGINE_VERSIONS)
    const unknown = await server.api('GET', '/api/audit/verify?serverSeed=s&clientSeed=c&nonce=1&engineVersion=0', operator)
    expect([unknown.status, unknown.body.code]).toEqual([400, 'E_UNKNOWN_ENGINE_VERSION'])
    // An export names exactly one history: one form-exploded query object whose oneOf says so, the very rule the server checks.
    const exported = openapi.paths['/api/audit/export'].get
    const [filter] = exported.parameters
    expect(exported.parameters).toHaveLength(1)
    expect(filter).toMatchObject({ in: 'query', style: 'form', explode: true, required: true })
    const ajv = new Ajv({ strict: false })
    const validate = ajv.compile(filter.schema)
    const hash = '0'.repeat(64)
    for (const [params, valid] of [[{}, false], [{ player: 'p' }, true], [{ serverSeedHash: hash, format: 'ndjson' }, true], [{ player: 'p', serverSeedHash: hash }, false]]) {
      expect(validate(params), JSON.stringify(params)).toBe(valid)
      const response = await server.api('GET', `/api/audit/export?${new URLSearchParams(params)}`, operator)
      expect(response.status, JSON.stringify(params)).toBe(valid ? 200 : 400)
      expect(exported.responses[response.status], JSON.stringify(params)).toBeDefined()
      if (valid) expect(Object.keys(exported.responses[200].content)).toContain(response.headers['content-type'].split(';')[0])
    }
  })

  it('documents POST /api/session\'s body: none or {}, and nothing else', () => {
    const body = openapi.paths['/api/session'].post.requestBody
    expect(body.required).toBe(false)
    expect(body.content['application/json'].schema).toMatchObject({ type: ['object', 'null'], additionalProperties: false })
  })

  it('publishes the WebSocket protocol as valid AsyncAPI 3.0, its client messages the schemas the server validates with', async () => {
    const response = await server.api('GET', '/api/asyncapi.json')
    expect(response.status).toBe(200)
    const asyncapi = response.body
    // The AsyncAPI schema embeds its own copy of the draft-07 meta-schema: Ajv's is left out.
    const ajv = new Ajv({ strict: false, allErrors: true, validateFormats: false, meta: false, validateSchema: false })
    const validate = ajv.compile(asyncApiSpecs.schemas['3.0.0'])
    expect(validate(asyncapi), ajv.errorsText(validate.errors)).toBe(true)
    expect(validate({ ...asyncapi, operations: { shout: { action: 'shout', channel: { $ref: '#/channels/game' } } } })).toBe(false)
    const messages = asyncapi.channels.game.messages
    const config = server.app.arena.config
    for (const [type, schema] of Object.entries(clientMessageSchemas(config))) expect(messages[type].payload, type).toEqual(schema)
    expect(messages.drop.payload.properties.bet).toMatchObject({ minimum: config.minBet, maximum: config.maxBet })
    // Every operation's messages are in the channel.
    for (const operation of Object.values(asyncapi.operations)) {
      for (const { $ref } of [...operation.messages, ...(operation.reply?.messages ?? [])]) expect(messages[$ref.split('/').pop()], $ref).toBeDefined()
    }
  })
})
