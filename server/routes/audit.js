import { Readable } from 'node:stream'
import { simulateDrop, verifyDrop, MIN_ROWS, MAX_ROWS, RISKS, ENGINE_VERSION, ENGINE_VERSIONS, isEngineVersion } from '../../engine/index.js'
import { requireOperator } from '../auth.js'
import { gameError } from '../errors.js'
import { deriveDropSeed, sha256Hex } from '../fairness/seeds.js'
import { payoutFor, toCredits } from '../game/money.js'
import { parseRoomId } from '../../protocol/room-id.js'
import { boardOf } from '../rooms/boards.js'
import { dropList, dropRecord, errors, parseTime, timeParam, TIME_PATTERN } from './schemas.js'

const hex64 = { type: 'string', pattern: '^[0-9a-f]{64}$' }
/** Printable ASCII only: a NUL or control character is no id (and PostgreSQL refuses NUL in text). */
const printable = '^[\\x20-\\x7e]*$'
const playerId = { type: 'string', minLength: 1, maxLength: 64, pattern: printable }
/** The shipped engine versions (engine/version.js), a closed set: any other is E_UNKNOWN_ENGINE_VERSION. */
const engineVersionParam = { type: 'string', enum: [...ENGINE_VERSIONS], default: ENGINE_VERSION, description: `an engine version of this server (default ${ENGINE_VERSION}, the newest)` }

/** An export names exactly one of the two histories: documented as one rule (api-docs.js turns it into one query object). */
const exportQuery = {
  type: 'object',
  properties: { player: playerId, serverSeedHash: hex64, format: { type: 'string', enum: ['json', 'ndjson'], default: 'json' } },
  oneOf: [{ required: ['player'] }, { required: ['serverSeedHash'] }],
  additionalProperties: false
}

/**
 * The audit routes' refusals by what failed: an engine version outside the
 * enum is E_UNKNOWN_ENGINE_VERSION, an export naming neither or both
 * histories says so, a time filter that is no time says what a time is; anything else is E_BAD_REQUEST with Ajv's words.
 * @param {import('ajv').ErrorObject[]} errors @param {string} part
 */
function auditSchemaError (errors, part) {
  if (errors.some((error) => error.instancePath === '/engineVersion')) {
    return gameError('E_UNKNOWN_ENGINE_VERSION', `no such engine version on this server (it has ${ENGINE_VERSIONS.join(', ')})`)
  }
  if (errors.some((error) => error.keyword === 'oneOf')) return gameError('E_BAD_REQUEST', 'give exactly one of player or serverSeedHash')
  // A time filter's pattern is long: say what it means.
  const time = errors.find((error) => error.keyword === 'pattern' && error.params.pattern === TIME_PATTERN)
  if (time) return gameError('E_BAD_REQUEST', `${time.instancePath.slice(1)} must be an ISO 8601 time or milliseconds since the epoch`)
  return gameError('E_BAD_REQUEST', errors.map((error) => `${part}${error.instancePath} ${error.message}`).join(', '))
}

/**
 * The operator API (Authorization: Bearer OPERATOR_TOKEN): any drop with a
 * fresh re-simulation, searches, a standalone verifier, full-history
 * exports and per-room statistics. Active server seeds are used for checks
 * but never returned.
 * @param {import('fastify').FastifyInstance} app
 * @param {object} services
 * @param {import('../store/ledger-store.js').LedgerStore} services.store
 * @param {{ get: (id: string) => import('../rooms/room.js').Room | undefined }} services.rooms this process's live rooms
 * @param {string} services.operatorToken
 * @param {import('../limits/auth-guard.js').AuthGuard} services.authGuard
 */
export default async function auditRoutes (app, { store, rooms, operatorToken, authGuard }) {
  // onRequest: the token is checked before anything of the request is (its query's schema included),
  // after the rate limit (a hook on each route, not the plugin's: those run before any route's).
  const operatorOnly = requireOperator(operatorToken, authGuard)
  app.addHook('onRoute', (route) => { route.onRequest = [...[route.onRequest ?? []].flat(), operatorOnly] })
  app.setSchemaErrorFormatter(auditSchemaError)
  dropLookupRoutes(app, store)
  verifyRoute(app, store)
  exportRoute(app, store)
  roomStatsRoute(app, store, rooms)
}

/** GET /api/audit/drops/:id (one drop, re-simulated) and /api/audit/drops (a search). */
function dropLookupRoutes (app, store) {
  app.get('/api/audit/drops/:id', {
    schema: {
      summary: 'A stored drop, its re-simulation from the stored seeds and whether they match',
      params: { type: 'object', properties: { id: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER } }, required: ['id'] },
      response: {
        200: {
          type: 'object',
          properties: {
            drop: dropRecord,
            replay: {
              type: ['object', 'null'],
              properties: {
                engineVersion: { type: 'string' },
                serverSeedHash: { type: ['string', 'null'] },
                dropSeed: { type: ['string', 'null'] },
                bucket: { type: 'integer' },
                multiplier: { type: 'number' },
                payout: { type: 'number' },
                ticks: { type: 'integer' },
                stateHash: { type: 'string' }
              }
            },
            checks: { type: 'object', additionalProperties: { type: ['boolean', 'null'] } },
            matches: { type: 'boolean' }
          }
        },
        ...errors(400, 401, 403, 404)
      }
    }
  }, async (request) => {
    const drop = await store.getDrop(request.params.id)
    if (!drop) throw gameError('E_NOT_FOUND', `no drop ${request.params.id}`)
    const serverSeed = await store.getServerSeedOfDrop(drop.id)
    return auditDrop(drop, serverSeed)
  })

  app.get('/api/audit/drops', {
    schema: {
      summary: 'Drops, newest first, filtered by player, room and creation time (by id; a player\'s in the order they were played: seed by seed, nonce by nonce); page with ?before=<id of the previous page\'s last drop>',
      querystring: {
        type: 'object',
        properties: {
          player: playerId,
          room: { type: 'string', maxLength: 32, pattern: printable },
          from: timeParam,
          to: timeParam,
          limit: { type: 'integer', minimum: 1, maximum: 1000, default: 100 },
          before: { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER }
        },
        additionalProperties: false
      },
      response: { 200: dropList, ...errors(400, 401, 403, 404) }
    }
  }, async (request) => {
    const { player, room, from, to, limit, before } = request.query
    return { drops: await store.listDrops({ playerId: player, room, from: timeFilter('from', from), to: timeFilter('to', to), beforeId: before, limit }) }
  })
}

/** GET /api/audit/verify: the chain of a drop given by its seeds, stored or not. */
function verifyRoute (app, store) {
  app.get('/api/audit/verify', {
    schema: {
      summary: 'Recompute a drop from seeds (through the engine\'s WebCrypto path, as a browser would)',
      querystring: {
        type: 'object',
        properties: {
          serverSeed: { type: 'string', minLength: 1, maxLength: 256 },
          clientSeed: { type: 'string', minLength: 1, maxLength: 64 },
          nonce: { type: 'integer', minimum: 0, maximum: Number.MAX_SAFE_INTEGER },
          rows: { type: 'integer', minimum: MIN_ROWS, maximum: MAX_ROWS, default: 16 },
          risk: { type: 'string', enum: [...RISKS], default: 'medium' },
          engineVersion: engineVersionParam
        },
        required: ['serverSeed', 'clientSeed', 'nonce'],
        additionalProperties: false
      },
      response: {
        200: {
          type: 'object',
          properties: {
            serverSeedHash: { type: 'string' },
            dropSeed: { type: 'string' },
            bucket: { type: 'integer' },
            multiplier: { type: 'number' },
            ticks: { type: 'integer' },
            stateHash: { type: 'string' },
            engineVersion: { type: 'string' },
            recorded: { type: 'array', items: { type: 'object', properties: { id: { type: 'integer' }, matches: { type: 'boolean' } } } }
          }
        },
        ...errors(400, 401, 403)
      }
    }
  }, async (request) => {
    const { serverSeed, clientSeed, nonce, rows, risk } = request.query
    const engineVersion = request.query.engineVersion
    const result = await verifyDrop({ serverSeed, clientSeed, nonce, rows, risk, engineVersion })
    // Any stored drop with these seeds, checked against the recomputation.
    const stored = await store.listDrops({ serverSeedHash: result.serverSeedHash, nonce, limit: 10 })
    const recorded = stored.map((drop) => ({
      id: drop.id,
      matches: drop.clientSeed === clientSeed && drop.dropSeed === result.dropSeed && drop.rows === rows && drop.risk === risk && drop.engineVersion === engineVersion &&
        (drop.status !== 'settled' || (drop.bucket === result.bucket && drop.ticks === result.ticks && drop.stateHash === result.stateHash))
    }))
    return { ...result, recorded }
  })
}

/** GET /api/audit/export: a player's or a seed's whole history. */
function exportRoute (app, store) {
  app.get('/api/audit/export', {
    schema: {
      summary: 'The full drop history of a player or of one server seed, oldest first, as JSON or JSON lines',
      description: 'Give exactly one of `player` and `serverSeedHash`. The body is streamed: a JSON array of drop records (`format=json`) or one record per line (`format=ndjson`).',
      querystring: exportQuery,
      response: {
        200: {
          description: 'The drops, oldest first, as an attachment',
          content: {
            'application/json': { schema: { type: 'array', items: dropRecord } },
            'application/x-ndjson': { schema: { type: 'string', description: 'one drop record (as in the JSON array) per line' } }
          }
        },
        ...errors(400, 401, 403)
      }
    }
  }, async (request, reply) => {
    const { player, serverSeedHash, format } = request.query
    const drops = store.iterateDrops({ playerId: player, serverSeedHash })
    reply.header('content-disposition', `attachment; filename="drops-${(player ?? serverSeedHash.slice(0, 16)).replace(/[^\w.-]/g, '_')}.${format === 'json' ? 'json' : 'ndjson'}"`)
    if (format === 'ndjson') {
      reply.type('application/x-ndjson')
      return reply.send(Readable.from(jsonLines(drops)))
    }
    reply.type('application/json')
    return reply.send(Readable.from(jsonArray(drops)))
  })
}

/** GET /api/audit/rooms/:id/stats: a room's settled drops by bucket and its measured RTP, live figures where it runs here. */
function roomStatsRoute (app, store, rooms) {
  app.get('/api/audit/rooms/:id/stats', {
    schema: {
      summary: 'A room\'s settled drops: totals, measured RTP and bucket counts (for the operator\'s charts)',
      params: { type: 'object', properties: { id: { type: 'string', maxLength: 32, description: 'a room id (`ROWS-RISK` or `ROWS-RISK.N`)', examples: ['16-medium', '8-low.2'] } }, required: ['id'] },
      querystring: { type: 'object', properties: { engineVersion: engineVersionParam }, additionalProperties: false },
      response: {
        200: {
          type: 'object',
          properties: {
            room: { type: 'string' },
            engineVersion: { type: 'string' },
            rows: { type: 'integer' },
            risk: { type: 'string' },
            multipliers: { type: 'array', items: { type: 'number' } },
            settled: { type: 'integer' },
            inFlight: { type: 'integer' },
            totalBet: { type: 'integer' },
            totalPayout: { type: 'number' },
            rtp: { type: ['number', 'null'] },
            bucketCounts: { type: 'array', items: { type: 'integer' } },
            buckets: {
              type: 'array',
              items: { type: 'object', properties: { bucket: { type: 'integer' }, count: { type: 'integer' }, bet: { type: 'integer' }, payout: { type: 'number' } } }
            },
            live: {
              type: ['object', 'null'],
              properties: { players: { type: 'integer' }, ballsInFlight: { type: 'integer' }, tick: { type: 'integer' } }
            }
          }
        },
        ...errors(400, 401, 403, 404)
      }
    }
  }, async (request) => {
    const id = request.params.id
    const parsed = parseRoomId(id)
    if (!parsed) throw gameError('E_UNKNOWN_ROOM', `no room ${JSON.stringify(id)}`)
    const engineVersion = request.query.engineVersion
    const stats = await store.roomStats(id, engineVersion)
    const board = boardOf(id, engineVersion)
    const bucketCounts = new Array(board.rows + 1).fill(0)
    for (const { bucket, count } of stats.buckets) bucketCounts[bucket] = count
    const live = rooms.get(id)
    return {
      room: id,
      engineVersion,
      ...parsed,
      multipliers: board.multipliers,
      ...stats,
      bucketCounts,
      live: live ? { players: live.clients.size, ballsInFlight: live.ballsInFlight, tick: live.tick } : null
    }
  })
}

/**
 * Re-simulates a stored drop from its drop seed, under the engine version
 * it was decided under, and checks every link of the chain the server can
 * check: commitment, HMAC, outcome, payout. A check is null when it does
 * not apply (an in-flight drop has no outcome yet); `matches` is true only
 * when every applicable check passed and the drop is settled. A drop of an
 * engine version this server does not have gets no replay (checks
 * engineVersion false).
 * @param {ReturnType<import('../store/records.js').toDropRecord>} drop
 * @param {string | null} serverSeed
 */
export function auditDrop (drop, serverSeed) {
  if (!isEngineVersion(drop.engineVersion)) {
    return { drop, replay: null, checks: { engineVersion: false }, matches: false }
  }
  const outcome = simulateDrop(boardOf(`${drop.rows}-${drop.risk}`, drop.engineVersion), drop.dropSeed)
  // Under the rule the drop was paid under (protocol/payout.js), in credits as the record shows it.
  const payout = toCredits(payoutFor(drop.bet, outcome.multiplier, drop.payoutRule))
  const replay = {
    engineVersion: drop.engineVersion,
    serverSeedHash: serverSeed === null ? null : sha256Hex(serverSeed),
    dropSeed: serverSeed === null ? null : deriveDropSeed(serverSeed, drop.clientSeed, drop.nonce),
    bucket: outcome.bucket,
    multiplier: outcome.multiplier,
    payout,
    ticks: outcome.ticks,
    stateHash: outcome.stateHash
  }
  const settled = drop.status === 'settled'
  const checks = {
    engineVersion: true,
    serverSeedHash: serverSeed === null ? null : replay.serverSeedHash === drop.serverSeedHash,
    dropSeed: serverSeed === null ? null : replay.dropSeed === drop.dropSeed,
    bucket: settled ? drop.bucket === replay.bucket : null,
    multiplier: settled ? drop.multiplier === replay.multiplier : null,
    payout: settled ? drop.payout === replay.payout : null,
    ticks: settled ? drop.ticks === replay.ticks : null,
    stateHash: settled ? drop.stateHash === replay.stateHash : null
  }
  const matches = settled && Object.values(checks).every((check) => check !== false)
  return { drop, replay, checks, matches }
}

function timeFilter (name, value) {
  const ms = parseTime(value)
  if (Number.isNaN(ms)) throw gameError('E_BAD_REQUEST', `${name} must be an ISO 8601 time or milliseconds since the epoch`)
  return ms
}

async function * jsonLines (drops) {
  for await (const drop of drops) yield JSON.stringify(drop) + '\n'
}

async function * jsonArray (drops) {
  let first = true
  yield '['
  for await (const drop of drops) {
    yield (first ? '\n' : ',\n') + JSON.stringify(drop)
    first = false
  }
  yield '\n]\n'
}
