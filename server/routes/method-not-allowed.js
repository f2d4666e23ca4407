import fp from 'fastify-plugin'
import { gameError } from '../errors.js'

/**
 * 405 for a method the path does not have (RFC 9110 §15.5.6), with an
 * `Allow` header listing the ones it has; 404 (the app's `notFound`) for a
 * path no route has at all. Registered before the routes: its onRoute hook
 * records every route's methods by its URL pattern, for every route at once
 * (no route has to declare its other methods).
 *
 * The answer is given in two places, because a miss reaches fastify in two
 * ways: a method no route of the path has is a 404 request, answered in
 * onRequest (before its body is parsed, so that a QUERY without a
 * Content-Type gets 405 rather than a parser's 400); a GET that only the
 * client's catch-all `/*` matched (GET /api/session) reaches the not-found
 * handler when no such file exists, and the path's own route decides.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ notFound: (request: import('fastify').FastifyRequest, reply: import('fastify').FastifyReply) => void }} options
 */
async function methodNotAllowed (app, { notFound }) {
  const routes = new RouteMethods()
  app.addHook('onRoute', (route) => routes.add(route.url, [route.method].flat()))

  app.addHook('onRequest', async (request, reply) => {
    if (!request.is404) return
    const allowed = routes.allowedFor(request.url)
    if (allowed.length > 0 && !allowed.includes(request.method)) return refuse(request, reply, allowed)
  })
  app.setNotFoundHandler((request, reply) => {
    const allowed = routes.allowedFor(request.url)
    if (allowed.length > 0 && !allowed.includes(request.method)) return refuse(request, reply, allowed)
    notFound(request, reply)
  })
}

function refuse (request, reply, allowed) {
  const { code, message } = gameError('E_METHOD_NOT_ALLOWED', `${request.method} is not a method of this path; it has ${allowed.join(', ')}`)
  return reply.code(405).header('allow', allowed.join(', ')).send({ code, message })
}

export default fp(methodNotAllowed, { name: 'plinko-method-not-allowed', fastify: '5.x' })

/**
 * The methods of each route URL pattern (fastify's syntax: `:name` for a
 * segment, `*` for the rest), and the methods a concrete path has: those of
 * the most specific pattern it matches, as the router picks (a static path
 * before a parametric one, a parametric one before a wildcard, a longer
 * wildcard prefix before a shorter one).
 */
export class RouteMethods {
  /** @type {Map<string, { pattern: RegExp, rank: number[], methods: Set<string> }>} */
  #byUrl = new Map()

  /** @param {string} url @param {string[]} methods */
  add (url, methods) {
    let entry = this.#byUrl.get(url)
    if (!entry) {
      entry = { ...compile(url), methods: new Set() }
      this.#byUrl.set(url, entry)
    }
    for (const method of methods) entry.methods.add(method.toUpperCase())
  }

  /** @param {string} url a request's URL (its query is ignored) @returns {string[]} sorted; empty when no pattern matches */
  allowedFor (url) {
    const path = url.split('?', 1)[0]
    let best = null
    for (const entry of this.#byUrl.values()) {
      if (entry.pattern.test(path) && (best === null || outranks(entry.rank, best.rank))) best = entry
    }
    return best ? [...best.methods].sort() : []
  }
}

/** A URL pattern as a RegExp, and its rank: [wildcard?, parametric?, -static prefix length]. */
function compile (url) {
  let source = ''
  let staticPrefix = -1
  let length = 0
  let parametric = false
  let wildcard = false
  for (const part of url.split(/(:[A-Za-z0-9_]+(?:\([^)]*\))?|\*)/)) {
    if (part === '') continue
    if (part === '*' || part.startsWith(':')) {
      if (staticPrefix < 0) staticPrefix = length
      if (part === '*') {
        wildcard = true
        source += '.*'
      } else {
        parametric = true
        source += '[^/]+'
      }
    } else {
      source += part.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')
      length += part.length
    }
  }
  if (staticPrefix < 0) staticPrefix = length
  return { pattern: new RegExp(`^${source}$`), rank: [wildcard ? 1 : 0, parametric ? 1 : 0, -staticPrefix] }
}

/** Lower ranks win, compared in order. */
function outranks (a, b) {
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return a[i] < b[i]
  return false
}
