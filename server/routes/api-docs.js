import fp from 'fastify-plugin'
import swagger from '@fastify/swagger'
import swaggerUi from '@fastify/swagger-ui'
import { createRequire } from 'node:module'
import { ERROR_CODES } from '../errors.js'
import { asyncApiDocument, asyncApiPage } from '../realtime/asyncapi-document.js'

const { version } = createRequire(import.meta.url)('../../package.json')

/**
 * The API's own description, built from the routes' JSON schemas:
 *   GET /api/openapi.json   OpenAPI 3.1 of every HTTP route (@fastify/swagger)
 *   GET /docs               the same, browsable (@fastify/swagger-ui; its page has no
 *                           inline script, so it runs under the app's CSP as it is)
 *   GET /api/asyncapi.json  the WebSocket protocol as AsyncAPI 3.0 (realtime/asyncapi-document.js)
 *   GET /docs/websocket     that document as a page
 * Registered before the routes (fastify-plugin: @fastify/swagger's onRoute
 * hook must see every route of the app). Error replies are documented from
 * ERROR_CODES: each status's response lists the codes that carry it.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ config: import('../config.js').Config }} options
 */
async function apiDocs (app, { config }) {
  /** Querystrings with a rule across their parameters (oneOf), by `METHOD url`: see withQueryRules. */
  const queryRules = new Map()
  await app.register(swagger, {
    openapi: {
      openapi: '3.1.0',
      info: {
        title: 'Plinko Arena HTTP API',
        version,
        description: 'Errors are `{ code, message }` (see the `Error` schema); every route checks its input against the schema shown and refuses unknown properties. ' +
          'The real-time game runs over the WebSocket at `GET /ws?token=…`: see [/docs/websocket](/docs/websocket) and [/api/asyncapi.json](/api/asyncapi.json). ' +
          'A method a path does not have (`TRACE /api/health`, `DELETE /api/session`) is answered 405 E_METHOD_NOT_ALLOWED with an `Allow` header listing the methods it has (RFC 9110 §15.5.6): see the `MethodNotAllowed` response.'
      },
      tags: [
        { name: 'player', description: 'Guest sessions, balances and the fairness seeds of the caller' },
        { name: 'public', description: 'No token' },
        { name: 'operator', description: 'Audit API: `Authorization: Bearer OPERATOR_TOKEN`' },
        { name: 'realtime', description: 'The WebSocket game protocol' },
        { name: 'pages', description: 'The browser pages and the modules they load' },
        { name: 'docs', description: 'This description' }
      ],
      components: {
        responses: {
          MethodNotAllowed: {
            description: 'Any path, any method it does not have: E_METHOD_NOT_ALLOWED',
            headers: { Allow: { description: 'the methods this path has, e.g. `GET, HEAD`', schema: { type: 'string' } } },
            content: { 'application/json': { schema: errorResponse(405) } }
          }
        },
        securitySchemes: {
          playerToken: { type: 'http', scheme: 'bearer', description: 'A session token from POST /api/session' },
          operatorToken: { type: 'http', scheme: 'bearer', description: 'OPERATOR_TOKEN (missing: 401, wrong: 403)' }
        },
        schemas: {
          Error: {
            type: 'object',
            description: Object.entries(ERROR_CODES).map(([code, { status, message }]) => `${code} (${status}): ${message}`).join('\n\n'),
            properties: { code: { type: 'string', enum: Object.keys(ERROR_CODES) }, message: { type: 'string' } },
            required: ['code', 'message']
          }
        }
      }
    },
    transform: (route) => documentRoute(route, queryRules),
    transformObject: ({ openapiObject }) => withQueryRules(withOptionalBodies(openapiObject), queryRules)
  })
  await app.register(swaggerUi, {
    routePrefix: '/docs',
    // No call to the public validator (its badge is an image from another origin, which the CSP refuses).
    validatorUrl: null,
    uiConfig: { deepLinking: true, docExpansion: 'list' },
    theme: { title: 'Plinko Arena API' }
  })

  app.get('/api/openapi.json', {
    config: { rateLimit: false },
    schema: { summary: 'This description, OpenAPI 3.1', tags: ['docs'], response: { 200: { type: 'object', additionalProperties: true, description: 'An OpenAPI 3.1 document' } } }
  }, async () => app.swagger())

  const protocol = (request) => asyncApiDocument(config, { version, host: request.host })
  app.get('/api/asyncapi.json', {
    config: { rateLimit: false },
    schema: { summary: 'The WebSocket protocol, AsyncAPI 3.0', tags: ['docs'], response: { 200: { type: 'object', additionalProperties: true, description: 'An AsyncAPI 3.0 document' } } }
  }, async (request) => protocol(request))

  app.get('/docs/websocket', {
    config: { rateLimit: false },
    schema: { summary: 'The WebSocket protocol, as a page', tags: ['docs'], response: { 200: { description: 'HTML', content: { 'text/html': { schema: { type: 'string' } } } } } }
  }, async (request, reply) => reply.type('text/html; charset=utf-8').send(asyncApiPage(protocol(request))))
}

export default fp(apiDocs, { name: 'plinko-api-docs', fastify: '5.x' })

/**
 * Codes only the WebSocket protocol raises (game moves, connection limits,
 * clustering): an HTTP route's error responses list the others.
 */
export const WEBSOCKET_ONLY_CODES = Object.freeze(['E_BAD_MESSAGE', 'E_UNKNOWN_TYPE', 'E_BAD_BET', 'E_INSUFFICIENT_FUNDS', 'E_NOT_IN_ROOM', 'E_ROOM_FULL', 'E_SLOW_CONSUMER', 'E_TOO_MANY_CONNECTIONS', 'E_WRONG_NODE', 'E_ROOM_MOVING', 'E_SEED_ROTATED'])

/** `{ code, message }` with the HTTP codes that carry `status`. */
function errorResponse (status) {
  const codes = Object.entries(ERROR_CODES).filter(([code, known]) => known.status === Number(status) && !WEBSOCKET_ONLY_CODES.includes(code))
  return {
    type: 'object',
    description: codes.length > 0 ? codes.map(([code, { message }]) => `${code}: ${message}`).join('; ') : 'Error',
    properties: { code: { type: 'string', ...(codes.length > 0 ? { enum: codes.map(([code]) => code) } : {}) }, message: { type: 'string' } },
    required: ['code', 'message']
  }
}

/**
 * OpenAPI describes query parameters one by one, so a rule across them (an
 * export names exactly one of `player` and `serverSeedHash`) has no place on
 * any of them. OpenAPI's own way is one object parameter serialised as
 * `style: form, explode: true` (each property its own `name=value`, as sent
 * today) whose schema carries the rule: a route whose querystring schema has
 * `oneOf` is documented so, with the very properties and `oneOf` the server
 * validates with.
 */
function withQueryRules (openapiObject, queryRules) {
  for (const [key, querystring] of queryRules) {
    const [method, url] = key.split(' ')
    const operation = openapiObject.paths[url.replace(/:(\w+)/g, '{$1}').replace(/\*/g, '{*}')]?.[method.toLowerCase()]
    if (!operation) continue
    const query = operation.parameters.filter((parameter) => parameter.in === 'query')
    operation.parameters = [
      ...operation.parameters.filter((parameter) => parameter.in !== 'query'),
      {
        name: 'query',
        in: 'query',
        required: true,
        style: 'form',
        explode: true,
        ...(querystring.description ? { description: querystring.description } : {}),
        schema: {
          type: 'object',
          properties: Object.fromEntries(query.map((parameter) => [parameter.name, parameter.schema])),
          oneOf: querystring.oneOf,
          additionalProperties: false
        }
      }
    ]
  }
  return openapiObject
}

/**
 * @fastify/swagger marks every request body required; a body whose schema
 * also allows null (POST /api/session: no body at all) is optional.
 */
function withOptionalBodies (openapiObject) {
  for (const operations of Object.values(openapiObject.paths)) {
    for (const operation of Object.values(operations)) {
      const schema = operation.requestBody?.content?.['application/json']?.schema
      if (schema && [schema.type].flat().includes('null')) operation.requestBody.required = false
    }
  }
  return openapiObject
}

/** What a route needs: a player's session token, the operator token, or nothing; or it checks the operator token without needing it. */
function accessOf (route) {
  const hooks = [route.onRequest ?? []].flat()
  if (hooks.some((hook) => hook.name === 'playerOnly')) return 'player'
  if (route.config?.tokenCheck) return 'token-check'
  // The audit routes check the operator token in a hook of their plugin (routes/audit.js), which onRoute does not see.
  if (route.url.startsWith('/api/audit/')) return 'operator'
  return 'public'
}

function tagOf (route, access) {
  if (access === 'token-check') return 'operator'
  if (access !== 'public') return access
  if (route.url === '/ws') return 'realtime'
  if (route.url.startsWith('/api/') || route.url === '/metrics') return 'public'
  return 'pages'
}

/**
 * @fastify/swagger's per-route transform: tags, security, and the error
 * responses every route can give (401/403 for tokens, 400 for input that
 * fails the schema, 404 for a path parameter naming nothing, 429 for the
 * per-IP rate limit, 500 for an API failure) as `{ code, message }`.
 */
function documentRoute ({ schema = {}, url, route }, queryRules) {
  // The client's files (@fastify/static hides its routes) and the page of this description are documented too.
  // A path with a backslash or a NUL can name no file: @fastify/static refuses it with 403.
  if (url === '/*' && schema.hide) {
    return {
      schema: {
        summary: 'The player page (`/`) and the client\'s files',
        tags: ['pages'],
        params: { type: 'object', properties: { '*': { type: 'string', description: 'a file of client/', examples: ['index.html', 'audit.html', 'favicon.svg'] } } },
        response: { 200: { description: 'A file of client/', type: 'null' }, 403: { ...errorResponse(403), description: 'E_FORBIDDEN: a path that can name no file (a backslash or a NUL in it)' }, 404: errorResponse(404) }
      },
      url
    }
  }
  if ((url === '/docs' || url === '/docs/') && schema.hide) return { schema: { summary: 'This description, browsable (Swagger UI)', tags: ['docs'], response: { 200: { description: 'HTML', type: 'null' } } }, url: '/docs' }
  if (schema.hide) return { schema, url }
  if (schema.querystring?.oneOf) for (const method of [route.method].flat()) queryRules.set(`${method} ${url}`, schema.querystring)
  const access = accessOf(route)
  const response = { ...(schema.response ?? { 200: { description: 'OK', type: 'null' } }) }
  const wanted = []
  if (access === 'player' || access === 'operator') wanted.push(401)
  if (access === 'operator') wanted.push(403)
  if (schema.body || schema.querystring || schema.params) wanted.push(400)
  if (url.includes(':') || url.includes('*')) wanted.push(404)
  if (route.config?.rateLimit !== false) wanted.push(429)
  if (url.startsWith('/api/')) wanted.push(500)
  for (const status of wanted) response[status] ??= {}
  for (const status of Object.keys(response)) if (Number(status) >= 400) response[status] = errorResponse(status)
  const documented = {
    ...schema,
    tags: schema.tags ?? [tagOf(route, access)],
    response,
    ...(access === 'player' ? { security: [{ playerToken: [] }] } : access === 'operator' ? { security: [{ operatorToken: [] }] } : {}),
    // The operator token, or none (OpenAPI's empty requirement): the check answers either.
    ...(access === 'token-check' ? { security: [{ operatorToken: [] }, {}] } : {})
  }
  if (url === '/ws') {
    documented.description = 'Upgrade to the game\'s WebSocket (see /docs/websocket and /api/asyncapi.json). A plain GET without an upgrade is 400 E_BAD_REQUEST.'
    delete response[200]
    documented.response = { 101: { description: 'Switching Protocols: the game protocol', type: 'null' }, ...response, 400: errorResponse(400) }
  }
  if (url === '/metrics') documented.response = { 200: { description: 'Prometheus text exposition format', content: { 'text/plain': { schema: { type: 'string' } } } } }
  return { schema: documented, url }
}
