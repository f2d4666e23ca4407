import { Connection, createMessageParser } from '../realtime/connection.js'
import { playerIdForToken } from '../auth.js'
import { ERROR_CODES, GameError, gameError } from '../errors.js'
import { TokenBucket } from '../limits/token-bucket.js'
import { IpLimits } from '../realtime/ip-limits.js'

/** How often IPs with nothing open and full buckets are forgotten. */
const IP_SWEEP_MS = 60_000

/**
 * GET /ws?token=TOKEN: the game's WebSocket. Browsers cannot set headers
 * on a WebSocket, so the session token travels in the query string (it is
 * redacted from logs). A bad or missing token still upgrades, then gets
 * `{type:"error", code:"E_UNAUTHORIZED"}` and close code 4401, so browser
 * clients can tell why.
 * @param {import('fastify').FastifyInstance} app
 * @param {object} services
 * @param {import('../arena.js').Arena} services.arena the game each connection plays (join, leave, drop)
 * @param {import('../store/ledger-store.js').LedgerStore} services.store
 * @param {import('../game/accounts.js').AccountBook} services.accounts
 * @param {import('../config.js').Config} services.config
 * @param {any} services.metrics
 * @param {import('../limits/auth-guard.js').AuthGuard} services.authGuard
 * @param {import('../limits/worker-share.js').WorkerShare} [services.workerShare] how many processes divide the per-IP budgets
 */
export default async function realtimeRoutes (app, { arena, store, accounts, config, metrics, authGuard, workerShare }) {
  const parseMessage = createMessageParser(config)
  /** Per client IP (request.ip: honours TRUST_PROXY): open sockets, drop and join buckets. And sockets in total. */
  const ipLimits = new IpLimits({
    dropRate: config.dropRatePerIp,
    joinRate: config.joinRatePerIp,
    messageRate: config.wsIpMessageRate,
    byteRate: config.wsIpByteRate,
    maxPayload: config.wsMaxPayload,
    maxSockets: config.wsMaxConnectionsPerIp,
    share: workerShare
  })
  let open = 0
  const sweeper = setInterval(() => ipLimits.sweep(), IP_SWEEP_MS).unref()
  app.addHook('onClose', async () => clearInterval(sweeper))
  app.get('/ws', {
    schema: {
      summary: 'WebSocket endpoint of the game protocol',
      querystring: { type: 'object', properties: { token: { type: 'string', maxLength: 128 } } }
    },
    // A plain GET (no Upgrade) gets a named error instead of the plugin's empty 404.
    handler: async () => { throw gameError('E_BAD_REQUEST', 'GET /ws needs a WebSocket upgrade: connect with a WebSocket client to /ws?token=TOKEN') },
    wsHandler: (socket, request) => {
      // Listeners go on synchronously (inside Connection) so no frame is lost while the token is checked.
      const connection = new Connection({
        socket,
        arena,
        parseMessage,
        metrics,
        log: request.log,
        softLimit: config.wsSoftBuffer,
        hardLimit: config.wsHardBuffer,
        messageLimiter: new TokenBucket({ rate: config.wsMessageRate, burst: config.wsMessageBurst })
      })
      const ip = request.ip
      if (open >= config.wsMaxConnections || ipLimits.atSocketLimit(ip)) {
        connection.sendError('E_TOO_MANY_CONNECTIONS')
        connection.drop(ERROR_CODES.E_TOO_MANY_CONNECTIONS.close, 'E_TOO_MANY_CONNECTIONS')
        return
      }
      open++
      connection.ipLimits = ipLimits.acquire(ip)
      socket.once('close', () => {
        open--
        ipLimits.release(connection.ipLimits)
      })
      if (!arena.accepting) {
        connection.sendError('E_UNAVAILABLE')
        connection.close(1001, 'E_UNAVAILABLE')
        return
      }
      authenticate({ store, accounts, authGuard }, ip, request.query.token).then((account) => {
        if (!connection.authenticated(account) && account) accounts.release(account)
      }, (error) => {
        if (error instanceof GameError) {
          connection.sendError(error.code, error.message)
          connection.close(1008, error.code)
          return
        }
        request.log.error({ err: error }, 'websocket authentication failed')
        connection.sendError('E_INTERNAL')
        connection.close(1011, 'E_INTERNAL')
      })
    }
  })
}

/** The token's account, or null; a wrong token counts against the address, which may be blocked (E_RATE_LIMITED). */
async function authenticate ({ store, accounts, authGuard }, ip, token) {
  await authGuard.admit('player', ip)
  const playerId = await playerIdForToken(store, token)
  if (!playerId && token !== undefined) await authGuard.failed('player', ip)
  return playerId ? accounts.acquire(playerId) : null
}
