import net from 'node:net'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import envSchema from 'env-schema'
import { LOG_FORMATS } from './log-format.js'
import { operatorTokenWeakness } from './operator-token-strength.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')
const LOG_LEVELS = ['fatal', 'error', 'warn', 'info', 'debug', 'trace', 'silent']
/** Snapshot rates that divide the 60 Hz tick evenly, so snapshots are exactly periodic. */
const SNAPSHOT_RATES = [1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30, 60]
const PROXY_KEYWORDS = ['loopback', 'linklocal', 'uniquelocal']

/**
 * An integer written in decimal (spaces around it allowed), from minimum to
 * maximum: the text is checked first, so "1e3", "0x10" and "1.0" are refused
 * (ajv's coercion alone would take them), then ajv coerces it to a number
 * and checks the range.
 */
function integer (minimum, maximum, fallback) {
  return {
    default: fallback,
    errorMessage: `must be an integer from ${minimum} to ${maximum}`,
    allOf: [{ type: 'string', pattern: '^\\s*-?\\d+\\s*$' }, { type: 'integer', minimum, maximum }]
  }
}

function oneOf (values, fallback) {
  return { type: 'string', enum: values, default: fallback, errorMessage: `must be one of ${values.join(', ')}` }
}

function nonEmpty (fallback) {
  return { type: 'string', pattern: '\\S', default: fallback, errorMessage: 'must not be empty' }
}

/**
 * Every environment variable the server reads, as the JSON schema
 * env-schema checks the environment against (on ajv; see loadConfig): its
 * default, its range, and the reason given when a value is refused
 * (`errorMessage`: the one nearest the failing rule). `writeOnly` marks a
 * secret, never echoed. An empty variable counts as unset. The README's
 * configuration table lists the same variables and defaults, by hand;
 * tests/server/config-schema.test.js fails when the two drift apart.
 */
export const CONFIG_SCHEMA = {
  type: 'object',
  additionalProperties: false,
  properties: {
    PORT: integer(0, 65535, '8080'),
    HOST: nonEmpty('0.0.0.0'),
    DATABASE_URL: {
      type: 'string',
      default: '',
      writeOnly: true,
      errorMessage: 'must be sqlite:PATH or postgres://user:password@host:port/database',
      anyOf: [{ const: '' }, { pattern: '^sqlite:' }, { pattern: '^postgres(ql)?://' }],
      if: { pattern: '^sqlite:' },
      then: { minLength: 'sqlite:'.length + 1, errorMessage: 'sqlite: needs a file path, e.g. sqlite:./data/plinko.sqlite' },
      else: { if: { pattern: '^postgres(ql)?://' }, then: { format: 'url', errorMessage: 'is not a valid postgres:// URL' } }
    },
    SQLITE_BUSY_TIMEOUT_MS: integer(0, 60000, '5000'),
    LEDGER_COMMIT_TICKS: integer(1, 15, '2'),
    OPERATOR_TOKEN: {
      type: 'string',
      default: '',
      writeOnly: true,
      anyOf: [{ const: '' }, { minLength: 24 }],
      errorMessage: 'must be at least 24 characters (or unset to generate one)'
    },
    SNAPSHOT_HZ: oneOf(SNAPSHOT_RATES.map(String), '20'),
    EVENT_HZ: oneOf(SNAPSHOT_RATES.map(String), '4'),
    SPECTATOR_EVENTS: oneOf(['snapshot', 'immediate'], 'snapshot'),
    STARTING_BALANCE: integer(0, Number.MAX_SAFE_INTEGER, '100000'),
    MIN_BET: integer(1, Number.MAX_SAFE_INTEGER, '1'),
    MAX_BET: integer(1, Number.MAX_SAFE_INTEGER, '1000000'),
    LOG_LEVEL: oneOf(LOG_LEVELS, 'info'),
    LOG_FORMAT: oneOf(LOG_FORMATS, 'auto'),
    DROP_RATE: integer(1, 10000, '20'),
    DROP_BURST: integer(1, 10000, '20'),
    DROP_RATE_PER_IP: integer(1, 1e6, '200'),
    JOIN_RATE: integer(1, 10000, '5'),
    JOIN_RATE_PER_IP: integer(1, 1e6, '50'),
    MAX_BALLS_PER_ROOM: integer(1, 4096, '500'),
    WS_MAX_PAYLOAD: integer(256, 1048576, '4096'),
    WS_SOFT_BUFFER: integer(1, 1 << 30, '65536'),
    WS_HARD_BUFFER: integer(1, 1 << 30, '1048576'),
    MAX_CATCH_UP_TICKS: integer(1, 600, '10'),
    HTTP_RATE_LIMIT: integer(1, 1e9, '600'),
    MONITORING_RATE_LIMIT: integer(1, 1e9, '600'),
    MONITORING_PORT: {
      type: 'string',
      default: '',
      errorMessage: 'must be a port from 0 to 65535, or unset (no monitoring listener)',
      pattern: '^\\s*(|\\d{1,4}|[1-5]\\d{4}|6[0-4]\\d{3}|65[0-4]\\d{2}|655[0-2]\\d|6553[0-5])\\s*$'
    },
    MONITORING_HOST: nonEmpty('127.0.0.1'),
    MONITORING_ON_PUBLIC_PORT: oneOf(['true', 'false'], 'false'),
    AUTH_FAILURE_LIMIT: integer(1, 1e9, '10'),
    AUTH_BLOCK_MS: integer(1000, 86_400_000, '60000'),
    HTTP_IDLE_TIMEOUT_MS: integer(100, 3600000, '30000'),
    HTTP_REQUEST_TIMEOUT_MS: integer(100, 3600000, '30000'),
    HTTP_HEADERS_TIMEOUT_MS: integer(100, 3600000, '10000'),
    HTTP_MAX_CONNECTIONS: integer(0, 1e7, '0'),
    HTTP_MAX_CONNECTIONS_PER_IP: integer(1, 1e7, '256'),
    SESSION_RATE_LIMIT: integer(1, 1e9, '30'),
    WS_MAX_CONNECTIONS: integer(1, 1e7, '10000'),
    WS_MAX_CONNECTIONS_PER_IP: integer(1, 1e7, '50'),
    WS_MESSAGE_RATE: integer(1, 1e6, '100'),
    WS_MESSAGE_BURST: integer(1, 1e6, '200'),
    WS_IP_MESSAGE_RATE: integer(1, 1e9, '500'),
    WS_IP_BYTE_RATE: integer(1024, 1e12, '262144'),
    WS_HEARTBEAT_MS: integer(100, 3600000, '30000'),
    SHUTDOWN_TIMEOUT_MS: integer(100, 3600000, '10000'),
    // See trustProxy() for what each form means.
    TRUST_PROXY: {
      type: 'string',
      default: 'false',
      errorMessage: `must be false, a number of proxy hops, or proxy addresses (IPs, subnets, ${PROXY_KEYWORDS.join(', ')})`,
      anyOf: [{ pattern: '^\\s*false\\s*$' }, { pattern: '^\\s*\\d+\\s*$' }, { format: 'proxy-list' }],
      allOf: [
        {
          if: { pattern: '^\\s*true\\s*$' },
          then: { not: {}, errorMessage: '"true" would believe the client\'s own X-Forwarded-For (its left-most address); give the number of proxies in front of the server (e.g. 1) or their addresses (e.g. 127.0.0.1, 10.0.0.0/8, loopback)' }
        },
        {
          if: { pattern: '^\\s*\\d+\\s*$' },
          then: { pattern: '^\\s*0*([1-9]|10)\\s*$', errorMessage: 'as a number of proxy hops must be from 1 to 10' }
        }
      ]
    },
    CLIENT_DIR: nonEmpty(path.join(ROOT, 'client')),
    // Clustering (server/cluster/): REDIS_URL turns it on; see the README's "Scaling out".
    REDIS_URL: {
      type: 'string',
      default: '',
      writeOnly: true,
      errorMessage: 'must be redis://[user:password@]host:port[/db] or rediss://…',
      anyOf: [{ const: '' }, { pattern: '^rediss?://' }],
      if: { pattern: '^rediss?://' },
      then: { format: 'url', errorMessage: 'is not a valid redis:// URL' }
    },
    PUBLIC_URL: {
      type: 'string',
      default: '',
      errorMessage: 'must be an absolute http:// or https:// URL',
      anyOf: [{ const: '' }, { format: 'http-url' }]
    },
    LEASE_TTL_MS: integer(300, 600_000, '5000')
  }
}

/**
 * @typedef {object} Config
 * @property {number} port @property {string} host
 * @property {{ kind: 'sqlite', file: string, busyTimeoutMs: number } | { kind: 'postgres', url: string }} database
 * @property {string} operatorToken @property {boolean} operatorTokenGenerated
 * @property {number} snapshotHz @property {number} startingBalance
 * @property {number} eventHz drop-events frames per second at most, per room, to seeds-mode sockets
 * @property {number} ledgerCommitTicks ticks a ledger transaction gathers at least (game/drop.js GroupCommit)
 * @property {'snapshot' | 'immediate'} spectatorEvents when the room hears of a drop: with its next snapshot (one frame), or as soon as it is committed (one `events` frame per room per batch)
 * @property {number} minBet @property {number} maxBet @property {string} logLevel
 * @property {'auto' | 'json' | 'pretty'} logFormat pretty logs and a banner on a terminal, JSON lines otherwise (server/log-format.js)
 * @property {number} dropRate drops per second per player (token bucket refill)
 * @property {number} dropBurst token bucket capacity
 * @property {number} dropRatePerIp drops per second from one client IP, all its sessions together (burst: 2 s worth)
 * @property {number} joinRate joins per second per player (burst: 2 s worth)
 * @property {number} joinRatePerIp joins per second from one client IP (burst: 2 s worth)
 * @property {number} maxBallsPerRoom @property {number} wsMaxPayload
 * @property {number} wsSoftBuffer bytes queued on a socket above which snapshots are skipped
 * @property {number} wsHardBuffer bytes queued on a socket above which it is closed
 * @property {number} maxCatchUpTicks @property {number} httpRateLimit per IP per minute
 * @property {number} monitoringRateLimit requests per IP per minute to /metrics, and apart to /api/health
 * @property {{ port: number | null, host: string, onPublicPort: boolean }} monitoring where /metrics and /api/health
 *   are served: their own listener (port null: none), and whether the public port answers them too
 * @property {number} authFailureLimit wrong operator or session tokens per IP per minute before the IP is blocked (limits/auth-failures.js)
 * @property {number} authBlockMs the first such block; each further one in a row lasts twice as long, up to an hour
 * @property {number} sessionRateLimit new sessions per IP per minute
 * @property {number} httpIdleTimeoutMs an HTTP connection idle this long is closed (also keep-alive between requests, capped at 5 s)
 * @property {number} httpRequestTimeoutMs a request must arrive whole (headers and body) within this
 * @property {number} httpHeadersTimeoutMs its headers within this (at most httpRequestTimeoutMs)
 * @property {number} httpMaxConnections HTTP connections in total, WebSockets included (0: 90% of the open-file limit; never more than that)
 * @property {number} httpMaxConnectionsPerIp HTTP connections per TCP peer address (off behind a proxy: TRUST_PROXY)
 * @property {number} wsMaxConnections open WebSockets in total
 * @property {number} wsMaxConnectionsPerIp open WebSockets per client IP
 * @property {number} wsMessageRate frames per second per connection (token bucket refill)
 * @property {number} wsMessageBurst token bucket capacity for frames per connection
 * @property {number} wsIpMessageRate frames per second received from one client IP over all its sockets
 * @property {number} wsIpByteRate payload bytes per second received from one client IP over all its sockets
 * @property {number} wsHeartbeatMs ping interval; a peer that misses a ping is dropped
 * @property {number} shutdownTimeoutMs bound on a graceful shutdown, after which the process exits anyway
 * @property {false | number | string[]} trustProxy which X-Forwarded-For hops to believe (see trustProxy()) @property {string} clientDir
 * @property {string} redisUrl '' = one process alone; set = clustered (server/cluster/)
 * @property {string} publicUrl how clients reach this process ('' = http://HOST:PORT once listening)
 * @property {number} leaseTtlMs room lease lifetime; a dead process's rooms move after at most this
 */

export class ConfigError extends Error {
  /** @param {string[]} problems each `NAME="value": reason` (`(value hidden)` for a secret), or a rule between variables */
  constructor (problems) {
    super('invalid configuration:\n  ' + problems.join('\n  '))
    this.name = 'ConfigError'
    this.code = 'E_CONFIG'
    this.problems = problems
  }
}

/**
 * The `format`s the schema names: `validate`, and for a list, `explain`:
 * which part of a refused value is wrong (added to the variable's general
 * reason).
 */
const FORMATS = {
  url: { validate: (text) => URL.canParse(text) },
  'http-url': { validate: (text) => URL.canParse(text) && ['http:', 'https:'].includes(new URL(text).protocol) },
  'proxy-list': {
    validate: (text) => text.split(',').every((entry) => isProxyAddress(entry.trim())),
    explain: (text) => `"${text.split(',').map((entry) => entry.trim()).find((entry) => !isProxyAddress(entry))}" is none of them`
  }
}

let schemaAjv
/**
 * env-schema's own ajv (type coercion, defaults, every error at once),
 * given the formats and the `errorMessage` annotation; made on the first
 * call, then handed back to env-schema as it is (so the schema is compiled once).
 */
function ajvOption () {
  return schemaAjv ?? {
    customOptions (fresh) {
      for (const [name, { validate }] of Object.entries(FORMATS)) fresh.addFormat(name, validate)
      fresh.addKeyword({ keyword: 'errorMessage', schemaType: 'string' }) // read by problemsOf()
      schemaAjv = fresh
      return fresh
    }
  }
}

/**
 * Reads and validates the configuration against CONFIG_SCHEMA; throws one
 * ConfigError listing every problem, so an operator fixes them all in one go.
 * @param {Record<string, string | undefined>} [env]
 * @returns {Readonly<Config>}
 */
export function loadConfig (env = process.env) {
  // Only the server's variables, and an empty one counts as unset (its default).
  const data = {}
  for (const name of CONFIG_VARIABLES) if (env[name] !== undefined && env[name] !== '') data[name] = env[name]
  let values
  try {
    values = envSchema({ schema: CONFIG_SCHEMA, data, env: false, dotenv: false, ajv: ajvOption() })
  } catch (error) {
    const problems = Array.isArray(error.errors) ? problemsOf(error.errors, env) : []
    if (problems.length === 0) throw error // not the environment's fault
    throw new ConfigError(problems)
  }
  const problems = []
  if (values.MAX_BET < values.MIN_BET) problems.push('MAX_BET must be >= MIN_BET')
  if (values.WS_HARD_BUFFER <= values.WS_SOFT_BUFFER) problems.push('WS_HARD_BUFFER must be > WS_SOFT_BUFFER')
  const weakness = values.OPERATOR_TOKEN === '' ? null : operatorTokenWeakness(values.OPERATOR_TOKEN)
  if (weakness) problems.push(`OPERATOR_TOKEN=(value hidden): ${weakness}`)
  if (values.REDIS_URL && !/^postgres(ql)?:\/\//.test(values.DATABASE_URL)) {
    problems.push('REDIS_URL (clustering) needs DATABASE_URL=postgres://…: the processes share one ledger')
  }
  if (problems.length > 0) throw new ConfigError(problems)

  const generated = values.OPERATOR_TOKEN === ''
  return Object.freeze({
    port: values.PORT,
    host: values.HOST,
    database: withBusyTimeout(database(values.DATABASE_URL), values.SQLITE_BUSY_TIMEOUT_MS),
    operatorToken: generated ? randomToken() : values.OPERATOR_TOKEN,
    operatorTokenGenerated: generated,
    snapshotHz: Number(values.SNAPSHOT_HZ),
    eventHz: Number(values.EVENT_HZ),
    ledgerCommitTicks: values.LEDGER_COMMIT_TICKS,
    spectatorEvents: values.SPECTATOR_EVENTS,
    startingBalance: values.STARTING_BALANCE,
    minBet: values.MIN_BET,
    maxBet: values.MAX_BET,
    logLevel: values.LOG_LEVEL,
    logFormat: values.LOG_FORMAT,
    dropRate: values.DROP_RATE,
    dropBurst: values.DROP_BURST,
    dropRatePerIp: values.DROP_RATE_PER_IP,
    joinRate: values.JOIN_RATE,
    joinRatePerIp: values.JOIN_RATE_PER_IP,
    maxBallsPerRoom: values.MAX_BALLS_PER_ROOM,
    wsMaxPayload: values.WS_MAX_PAYLOAD,
    wsSoftBuffer: values.WS_SOFT_BUFFER,
    wsHardBuffer: values.WS_HARD_BUFFER,
    maxCatchUpTicks: values.MAX_CATCH_UP_TICKS,
    httpRateLimit: values.HTTP_RATE_LIMIT,
    monitoringRateLimit: values.MONITORING_RATE_LIMIT,
    monitoring: monitoringListener(values),
    authFailureLimit: values.AUTH_FAILURE_LIMIT,
    authBlockMs: values.AUTH_BLOCK_MS,
    httpIdleTimeoutMs: values.HTTP_IDLE_TIMEOUT_MS,
    httpRequestTimeoutMs: values.HTTP_REQUEST_TIMEOUT_MS,
    httpHeadersTimeoutMs: Math.min(values.HTTP_HEADERS_TIMEOUT_MS, values.HTTP_REQUEST_TIMEOUT_MS),
    httpMaxConnections: values.HTTP_MAX_CONNECTIONS,
    httpMaxConnectionsPerIp: values.HTTP_MAX_CONNECTIONS_PER_IP,
    sessionRateLimit: values.SESSION_RATE_LIMIT,
    wsMaxConnections: values.WS_MAX_CONNECTIONS,
    wsMaxConnectionsPerIp: values.WS_MAX_CONNECTIONS_PER_IP,
    wsMessageRate: values.WS_MESSAGE_RATE,
    wsMessageBurst: values.WS_MESSAGE_BURST,
    wsIpMessageRate: values.WS_IP_MESSAGE_RATE,
    wsIpByteRate: values.WS_IP_BYTE_RATE,
    wsHeartbeatMs: values.WS_HEARTBEAT_MS,
    shutdownTimeoutMs: values.SHUTDOWN_TIMEOUT_MS,
    trustProxy: trustProxy(values.TRUST_PROXY),
    clientDir: path.resolve(values.CLIENT_DIR),
    redisUrl: values.REDIS_URL,
    publicUrl: values.PUBLIC_URL.replace(/\/+$/, ''),
    leaseTtlMs: values.LEASE_TTL_MS
  })
}

/** Names of all variables, for documentation and tests. */
export const CONFIG_VARIABLES = Object.freeze(Object.keys(CONFIG_SCHEMA.properties))

/**
 * One problem per refused variable, in the schema's order: `NAME="value":
 * reason`, the reason being the `errorMessage` nearest the failing rule
 * (the deepest, when several rules failed: "sqlite: needs a file path"
 * rather than the variable's general form; a general reason gets what a
 * failed format explains). Secrets are never echoed, even when invalid.
 * @param {import('ajv').ErrorObject[]} errors @param {Record<string, string | undefined>} env
 */
function problemsOf (errors, env) {
  const reasons = new Map()
  const details = new Map()
  for (const error of errors) {
    const name = error.instancePath.split('/')[1]
    const found = nearestErrorMessage(error.schemaPath)
    if (!name || !found) continue
    if (!reasons.has(name) || found.depth > reasons.get(name).depth) reasons.set(name, found)
    const explain = error.keyword === 'format' ? FORMATS[error.params.format]?.explain : undefined
    if (explain) details.set(name, explain(env[name]))
  }
  return CONFIG_VARIABLES.filter((name) => reasons.has(name)).map((name) => {
    const shown = CONFIG_SCHEMA.properties[name].writeOnly ? '(value hidden)' : JSON.stringify(env[name])
    const { message, depth } = reasons.get(name)
    const detail = depth === GENERAL_DEPTH && details.has(name) ? `; ${details.get(name)}` : ''
    return `${name}=${shown}: ${message}${detail}`
  })
}

/** Where a variable's own errorMessage sits in a schema path: properties/NAME. */
const GENERAL_DEPTH = 1

/** @param {string} schemaPath e.g. '#/properties/DATABASE_URL/then/minLength' @returns {{ message: string, depth: number } | undefined} */
function nearestErrorMessage (schemaPath) {
  const steps = schemaPath.replace(/^#\//, '').split('/')
  let schema = CONFIG_SCHEMA
  let found
  for (let depth = 0; depth < steps.length && schema && typeof schema === 'object'; depth++) {
    schema = schema[steps[depth]]
    if (typeof schema?.errorMessage === 'string') found = { message: schema.errorMessage, depth }
  }
  return found
}

/** SQLite: how long a write waits for another process's write lock before failing with E_UNAVAILABLE. */
function withBusyTimeout (database, busyTimeoutMs) {
  return database.kind === 'sqlite' ? { ...database, busyTimeoutMs } : database
}

function randomToken () {
  const bytes = new Uint8Array(32)
  globalThis.crypto.getRandomValues(bytes)
  return Buffer.from(bytes).toString('hex')
}

/** DATABASE_URL, checked by the schema: '' → the default SQLite file; sqlite:PATH; postgres://… or postgresql://… */
function database (url) {
  if (url === '') return { kind: 'sqlite', file: path.join(ROOT, 'data', 'plinko.sqlite') }
  if (url.startsWith('sqlite:')) {
    const file = url.slice('sqlite:'.length)
    return { kind: 'sqlite', file: file === ':memory:' ? file : path.resolve(file) }
  }
  return { kind: 'postgres', url }
}

/**
 * TRUST_PROXY, checked by the schema: which X-Forwarded-For hops to
 * believe. 'false' (none: the socket's peer is the client), a number N of
 * proxies in front of the server, 1 to 10 (the client is the Nth address
 * from the right: what the nearest proxy saw), or the proxies' addresses
 * (IPs, CIDR subnets, or loopback / linklocal / uniquelocal,
 * comma-separated). 'true' is refused: it believes every hop, and the
 * client writes the left-most one itself.
 * @param {string} text @returns {false | number | string[]}
 */
function trustProxy (text) {
  const value = text.trim()
  if (value === 'false') return false
  if (/^\d+$/.test(value)) return Number(value)
  return value.split(',').map((entry) => entry.trim())
}

/** An IP, an IP/prefix (at most 32 bits for IPv4, 128 for IPv6) or one of PROXY_KEYWORDS. */
function isProxyAddress (entry) {
  if (PROXY_KEYWORDS.includes(entry)) return true
  const [address, prefix, extra] = entry.split('/')
  const family = net.isIP(address)
  const validPrefix = prefix === undefined || (/^\d+$/.test(prefix) && Number(prefix) <= (family === 6 ? 128 : 32))
  return family !== 0 && validPrefix && extra === undefined
}

/**
 * MONITORING_PORT unset: /metrics and /api/health on the public port, as
 * ever. Set: on a listener of their own (MONITORING_HOST, loopback by
 * default), and on the public port only with MONITORING_ON_PUBLIC_PORT=true.
 */
function monitoringListener (values) {
  const port = values.MONITORING_PORT.trim() === '' ? null : Number(values.MONITORING_PORT)
  return { port, host: values.MONITORING_HOST, onPublicPort: port === null || values.MONITORING_ON_PUBLIC_PORT === 'true' }
}
