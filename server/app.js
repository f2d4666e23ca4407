import Fastify from 'fastify'
import helmet from '@fastify/helmet'
import compress from '@fastify/compress'
import { constants as zlibConstants } from 'node:zlib'
import rateLimit from '@fastify/rate-limit'
import websocket from '@fastify/websocket'
import { Arena } from './arena.js'
import { GameError, gameError } from './errors.js'
import { createMetrics } from './metrics.js'
import { modeOf } from './coordination/modes.js'
import { SeedChanges } from './game/seed-changes.js'
import { AuthGuard } from './limits/auth-guard.js'
import { ConnectionLimits, connectionCeiling } from './limits/connection-limits.js'
import { WEBSOCKET_OPTIONS } from './realtime/outgoing-message.js'
import apiDocs from './routes/api-docs.js'
import methodNotAllowed from './routes/method-not-allowed.js'
import sessionRoutes from './routes/session.js'
import seedRoutes from './routes/seeds.js'
import dropRoutes from './routes/drops.js'
import shareRoutes from './routes/share.js'
import roomRoutes from './routes/rooms.js'
import clientReportRoutes from './routes/client-reports.js'
import engineSpecRoutes from './routes/engine-spec.js'
import auditRoutes from './routes/audit.js'
import auditTokenCheckRoute from './routes/audit-token-check.js'
import metricsRoutes from './routes/metrics.js'
import healthRoutes from './routes/health.js'
import realtimeRoutes from './routes/realtime.js'
import clientRoutes from './routes/client.js'
import clientAssetRoutes, { inlineScriptHashes } from './routes/client-assets.js'
import { requestValidatorCompiler } from './routes/request-validation.js'
import { clientErrorHandler, requireHost } from './routes/client-errors.js'

/** Longest an idle keep-alive connection stays open between requests. */
const KEEP_ALIVE_MS = 5000

/**
 * Builds the whole server without listening: tests drive it with
 * app.inject() or listen on port 0; server.js listens on the configured
 * port. Chooses the mode once (coordination/modes.js: alone, or clustered
 * with REDIS_URL), opens (and migrates) its ledger, starts its coordination
 * (which settles the drops a previous process left in flight), then wires
 * the arena and the routes. The 60 Hz clock starts when the app is ready
 * and stops (after settling every ball in flight) when it closes.
 * @param {import('./config.js').Config} config
 * @param {object} [options]
 * @param {any} [options.store] an opened, migrated store (default: from config.database); the app closes it
 * @param {number} [options.tickRate] wall-clock ticks per second (default 60; tests may run faster —
 *   the simulation still advances 1/60 s per tick, so outcomes are unchanged)
 * @param {object} [options.logger] fastify logger options, or false
 * @param {object} [options.logOutput] where the default logger writes: `{ transport }` or `{ stream }` (server/log-format.js: pino-pretty on a terminal, synchronous JSON lines otherwise)
 * @param {boolean} [options.announceToken] log a generated operator token (default true; false when the start-up banner shows it)
 */
export async function buildApp (config, options = {}) {
  const app = createFastify(config, options)
  const { store, coordination, metrics, arena, addressLimits } = await startGame(app, config, options)
  const authGuard = new AuthGuard({ limiter: addressLimits.authFailures, metrics, log: app.log })
  await registerPlugins(app, { config, arena, addressLimits })
  await registerRoutes(app, { config, store, coordination, metrics, arena, authGuard, addressLimits })
  await monitoringListener(app, config, { metrics, arena })
  app.addHook('onReady', async () => arena.run())
  app.addHook('onClose', async () => {
    arena.scheduler.stop()
    await coordination.close()
    await addressLimits.close()
    await store.close()
  })
  return app
}

/** Fastify with the server's logger, timeouts and named errors for what fails before routing. */
function createFastify (config, options) {
  const app = Fastify({
    logger: options.logger ?? {
      level: config.logLevel,
      ...options.logOutput,
      redact: ['req.headers.authorization'],
      serializers: { req: (request) => ({ method: request.method, url: redactToken(request.url), remoteAddress: request.ip }) }
    },
    trustProxy: config.trustProxy,
    bodyLimit: 16 * 1024,
    // While closing, requests still go through the routes (a WebSocket then gets
    // E_UNAVAILABLE and 1001). Fastify's own 503 leaves an upgrade's socket open,
    // and that socket would hold the shutdown until SHUTDOWN_TIMEOUT_MS.
    return503OnClosing: false,
    // Idle and slow HTTP connections are closed, so they cannot pile up (a
    // WebSocket leaves these behind: ws clears the socket's timeout on upgrade).
    connectionTimeout: config.httpIdleTimeoutMs,
    keepAliveTimeout: Math.min(KEEP_ALIVE_MS, config.httpIdleTimeoutMs),
    requestTimeout: config.httpRequestTimeoutMs,
    // Node checks for requests past their timeout on this period (default 30 s): a slow
    // sender (slowloris) is answered 408 and closed within about one period of its deadline
    // (its headers' deadline: HTTP_HEADERS_TIMEOUT_MS).
    // Missing Host is refused by requireHost (with a code), not by Node (with an empty body).
    http: { connectionsCheckingInterval: Math.min(1000, config.httpHeadersTimeoutMs), headersTimeout: config.httpHeadersTimeoutMs, requireHostHeader: false },
    // Errors raised before routing (a malformed URL such as '/%') get a named code too.
    // Parser errors, header overflow and slow senders get a named code too (routes/client-errors.js).
    clientErrorHandler,
    frameworkErrors: (error, request, reply) => {
      reply.code(400).send({ code: 'E_BAD_REQUEST', message: error.message })
    },
  })
  app.addHook('onRequest', requireHost)
  // Safe integers only, bodies as sent, no extra properties (routes/request-validation.js).
  app.setValidatorCompiler(requestValidatorCompiler())
  app.setErrorHandler(replyWithError)
  if (config.operatorTokenGenerated && options.announceToken !== false) {
    app.log.warn({ operatorToken: config.operatorToken }, 'OPERATOR_TOKEN not set; generated this one for the operator API (set OPERATOR_TOKEN to keep it across restarts)')
  }
  return app
}

/**
 * Chooses the mode, opens its ledger and starts the arena on it (its
 * room ownership settles what a previous process left in flight); caps the
 * connections and says where per-address limits are counted.
 */
async function startGame (app, config, options) {
  const mode = modeOf(config)
  const store = options.store ?? await mode.openStore(config.database)
  const coordination = mode.coordinate({ store, config, log: app.log })
  const { ownership, sequences, feed } = coordination
  const metrics = createMetrics()
  const arena = new Arena({ config, store, ownership, sequences, feed, metrics, log: app.log, tickRate: options.tickRate })
  try {
    await arena.start()
  } catch (error) {
    await coordination.close().catch(() => {})
    await store.close().catch(() => {})
    throw error
  }
  // Connections in total and per peer, the longest idle shed first (limits/connection-limits.js).
  new ConnectionLimits({
    maxTotal: connectionCeiling(config.httpMaxConnections),
    maxPerAddress: config.trustProxy === false ? config.httpMaxConnectionsPerIp : null,
    metrics
  }).attach(app.server)
  const addressLimits = mode.createAddressLimits({ config, log: app.log })
  metrics.addressShareWorkers.set(addressLimits.workerShare.workers)
  addressLimits.workerShare.onChange((workers) => metrics.addressShareWorkers.set(workers))
  app.decorate('arena', arena)
  app.addHook('onListen', async () => {
    const address = app.server.address()
    if (address && typeof address === 'object') ownership.setListenUrl(`http://${address.family === 'IPv6' ? `[${address.address}]` : address.address}:${address.port}`)
  })
  return { store, coordination, metrics, arena, addressLimits }
}

/** Security headers, compression, the HTTP rate limit and WebSockets (which close after the arena). */
async function registerPlugins (app, { config, arena, addressLimits }) {
  await app.register(helmet, {
    contentSecurityPolicy: { directives: { upgradeInsecureRequests: null, imgSrc: ["'self'", 'data:'], workerSrc: ["'self'"], scriptSrc: ["'self'", ...inlineScriptHashes(config.clientDir)] } }
  })
  // Pages, modules and JSON compressed (a page load is ~290 KB of plain modules; ~4× less compressed).
  // Brotli at quality 5: most of quality 11's ratio at a fraction of its CPU, for every reply.
  await app.register(compress, { encodings: ['br', 'gzip'], brotliOptions: { params: { [zlibConstants.BROTLI_PARAM_QUALITY]: 5 } } })
  await app.register(rateLimit, {
    max: config.httpRateLimit,
    timeWindow: 60_000,
    errorResponseBuilder: (request, context) => gameError('E_RATE_LIMITED', `rate limit exceeded; retry in ${context.after}`),
    // A request whose socket is already gone (a malformed chunked body, say) has no address:
    // counted under one key rather than crashing the hook with a logged stack trace per request.
    keyGenerator: (request) => request.ip ?? 'unknown',
    ...addressLimits.rateLimitOptions
  })
  app.addHook('onRoute', rateLimitBeforeAuth)
  await app.register(websocket, {
    options: { maxPayload: config.wsMaxPayload, ...WEBSOCKET_OPTIONS },
    // Settle every ball in flight and say goodbye before the sockets go;
    // sockets that never authenticated are closed too, or close would wait for them.
    preClose (done) {
      const wss = this.websocketServer
      arena.close().then(() => {
        for (const socket of wss.clients) socket.close(1001, 'server shutting down')
        wss.close(() => done())
      }, done)
    }
  })
}

/** Every route, each given the services it uses, not the whole arena. */
async function registerRoutes (app, { config, store, coordination, metrics, arena, authGuard, addressLimits }) {
  const { ownership, feed } = coordination
  // Before the routes: its onRoute hook documents every route registered after it.
  await app.register(apiDocs, { config })
  // Also before them: 405 with Allow for a method a path does not have, 404 for a path no route has.
  await app.register(methodNotAllowed, {
    notFound: (request, reply) => reply.code(404).send({ code: 'E_NOT_FOUND', message: `no route ${request.method} ${redactToken(request.url)}` })
  })
  const { accounts } = arena
  const seedChanges = new SeedChanges({ ledger: arena.ledger, store, feed })
  await app.register(sessionRoutes, { config, store, accounts, authGuard })
  await app.register(seedRoutes, { store, accounts, seedChanges, authGuard })
  await app.register(dropRoutes, { store, authGuard })
  await app.register(shareRoutes, { store })
  await app.register(roomRoutes, { ownership })
  await app.register(clientReportRoutes)
  await app.register(engineSpecRoutes)
  if (config.monitoring.onPublicPort) await registerMonitoring(app, config, { metrics, arena })
  await app.register(realtimeRoutes, { arena, store, accounts, config, metrics, authGuard, workerShare: addressLimits.workerShare })
  await app.register(auditRoutes, { store, rooms: arena.rooms, operatorToken: config.operatorToken, authGuard })
  await app.register(auditTokenCheckRoute, { operatorToken: config.operatorToken, authGuard })
  await app.register(clientRoutes, { clientDir: config.clientDir })
  await app.register(clientAssetRoutes, { clientDir: config.clientDir })
}

/** /api/health and /metrics (each with its MONITORING_RATE_LIMIT where the rate limit is registered). */
async function registerMonitoring (app, config, { metrics, arena }) {
  await app.register(healthRoutes, { health: () => arena.health(), rateLimit: config.monitoringRateLimit })
  await app.register(metricsRoutes, { metrics, rateLimit: config.monitoringRateLimit })
}

/**
 * MONITORING_PORT set: /api/health and /metrics on a listener of their own
 * (MONITORING_HOST, loopback by default), so that probes and scrapes never
 * queue behind the public port's traffic and a client flooding the public
 * port cannot make the server render them. No rate limit there: whoever
 * reaches it is trusted. It listens when the app is ready (a port in use
 * stops the start) and closes with it; `app.monitoring` is its instance.
 */
async function monitoringListener (app, config, services) {
  const { port, host } = config.monitoring
  if (port === null) return
  // No line per probe or scrape (fastify 5.8+ takes this from a LogController).
  const logController = new Fastify.LogController({ disableRequestLogging: true })
  const monitoring = Fastify({ loggerInstance: app.log.child({ listener: 'monitoring' }), logController })
  monitoring.setErrorHandler(replyWithError)
  await registerMonitoring(monitoring, config, services)
  app.decorate('monitoring', monitoring)
  app.addHook('onReady', async () => {
    await monitoring.listen({ port, host })
    app.log.info({ address: monitoring.addresses()[0] }, 'monitoring listener: /api/health and /metrics')
  })
  app.addHook('onClose', async () => monitoring.close())
}

/** The hooks that check a token (server/auth.js). */
const AUTH_HOOKS = new Set(['playerOnly', 'operatorOnly'])

/**
 * onRoute, after the rate limit's own (which appends its hook to the route's
 * onRequest): the token checks move behind it, so a request is counted by
 * HTTP_RATE_LIMIT before its token is looked at, one with no token at all
 * (401) included. A plugin's own onRequest hooks run before any route's,
 * so the operator routes add theirs to each route too (routes/audit.js).
 */
function rateLimitBeforeAuth (route) {
  const hooks = [route.onRequest ?? []].flat()
  route.onRequest = [...hooks.filter((hook) => !AUTH_HOOKS.has(hook.name)), ...hooks.filter((hook) => AUTH_HOOKS.has(hook.name))]
}

/** HTTP errors as `{ code, message }`: named codes keep their status, bad input is a 4xx, never a 500. */
/** Named codes of fastify's own 4xx errors (body parser, routing, rate limit); any other 4xx is E_BAD_REQUEST. */
const CODE_OF_STATUS = { 401: 'E_UNAUTHORIZED', 403: 'E_FORBIDDEN', 404: 'E_NOT_FOUND', 413: 'E_PAYLOAD_TOO_LARGE', 415: 'E_UNSUPPORTED_MEDIA_TYPE', 429: 'E_RATE_LIMITED' }

function replyWithError (error, request, reply) {
  if (error instanceof GameError) {
    if (error.statusCode >= 500) request.log.error({ err: error }, error.message)
    reply.code(error.statusCode).send({ code: error.code, message: error.message })
    return
  }
  if (error.validation) {
    const first = error.validation[0]
    const code = error.validationContext === 'body' && first?.instancePath === '/clientSeed' ? 'E_BAD_SEED' : 'E_BAD_REQUEST'
    reply.code(400).send({ code, message: error.message })
    return
  }
  const status = error.statusCode
  if (Number.isInteger(status) && status >= 400 && status < 500) {
    const code = CODE_OF_STATUS[status] ?? 'E_BAD_REQUEST'
    reply.code(status).send({ code, message: error.message })
    return
  }
  request.log.error({ err: error }, 'request failed')
  reply.code(500).send({ code: 'E_INTERNAL', message: 'internal error' })
}

/** Session tokens ride in the WebSocket URL; keep them out of logs. @param {string} url */
export function redactToken (url) {
  return url.replace(/([?&]token=)[^&]*/gi, '$1[redacted]')
}
