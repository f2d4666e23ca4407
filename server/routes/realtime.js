import { Connection } from '../realtime/connection.js'
import { createMessageParser } from '../realtime/message-schemas.js'
import { playerIdForToken } from '../auth.js'

/**
 * GET /ws?token=TOKEN: the game's WebSocket. Browsers cannot set headers
 * on a WebSocket, so the session token travels in the query string (it is
 * redacted from logs). A bad or missing token still upgrades, then gets
 * `{type:"error", code:"E_UNAUTHORIZED"}` and close code 4401, so browser
 * clients can tell why.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ arena: import('../arena.js').Arena }} options
 */
export default async function realtimeRoutes (app, { arena }) {
  const { config, metrics } = arena
  const parseMessage = createMessageParser(config)
  app.get('/ws', {
    websocket: true,
    schema: {
      summary: 'WebSocket endpoint of the game protocol',
      querystring: { type: 'object', properties: { token: { type: 'string', maxLength: 128 } } }
    }
  }, (socket, request) => {
    // Listeners go on synchronously (inside Connection) so no frame is lost while the token is checked.
    const connection = new Connection({
      socket,
      arena,
      parseMessage,
      metrics,
      log: request.log,
      softLimit: config.wsSoftBuffer,
      hardLimit: config.wsHardBuffer
    })
    if (!arena.accepting) {
      connection.sendError('E_UNAVAILABLE')
      connection.close(1001, 'E_UNAVAILABLE')
      return
    }
    authenticate(arena, request.query.token).then((account) => {
      if (!connection.authenticated(account) && account) arena.accounts.release(account)
    }, (error) => {
      request.log.error({ err: error }, 'websocket authentication failed')
      connection.sendError('E_INTERNAL')
      connection.close(1011, 'E_INTERNAL')
    })
  })
}

async function authenticate (arena, token) {
  const playerId = await playerIdForToken(arena.store, token)
  return playerId ? arena.accounts.acquire(playerId) : null
}
