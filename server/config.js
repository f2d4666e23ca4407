import net from 'node:net'
import path from 'node:path'
import { fileURLToPath } from 'node:url'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')
const LOG_LEVELS = ['fatal', 'error', 'warn', 'info', 'debug', 'trace', 'silent']
/** Snapshot rates that divide the 60 Hz tick evenly, so snapshots are exactly periodic. */
const SNAPSHOT_RATES = [1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30, 60]

/**
 * Every environment variable the server reads, with its default and rule.
 * The README's configuration table is generated from this list by hand:
 * keep them in step.
 */
const VARIABLES = {
  PORT: { default: '8080', parse: integer(0, 65535) },
  HOST: { default: '0.0.0.0', parse: nonEmpty },
  DATABASE_URL: { default: '', parse: databaseUrl, secret: true },
  SQLITE_BUSY_TIMEOUT_MS: { default: '5000', parse: integer(0, 60000) },
  OPERATOR_TOKEN: { default: '', parse: operatorToken, secret: true },
  SNAPSHOT_HZ: { default: '20', parse: oneOf(SNAPSHOT_RATES.map(String), Number) },
  SPECTATOR_EVENTS: { default: 'snapshot', parse: oneOf(['snapshot', 'immediate']) },
  STARTING_BALANCE: { default: '100000', parse: integer(0, Number.MAX_SAFE_INTEGER) },
  MIN_BET: { default: '1', parse: integer(1, Number.MAX_SAFE_INTEGER) },
  MAX_BET: { default: '1000000', parse: integer(1, Number.MAX_SAFE_INTEGER) },
  LOG_LEVEL: { default: 'info', parse: oneOf(LOG_LEVELS) },
  DROP_RATE: { default: '20', parse: integer(1, 10000) },
  DROP_BURST: { default: '20', parse: integer(1, 10000) },
  DROP_RATE_PER_IP: { default: '200', parse: integer(1, 1e6) },
  JOIN_RATE: { default: '5', parse: integer(1, 10000) },
  JOIN_RATE_PER_IP: { default: '50', parse: integer(1, 1e6) },
  MAX_BALLS_PER_ROOM: { default: '500', parse: integer(1, 4096) },
  WS_MAX_PAYLOAD: { default: '4096', parse: integer(256, 1048576) },
  WS_SOFT_BUFFER: { default: '65536', parse: integer(1, 1 << 30) },
  WS_HARD_BUFFER: { default: '1048576', parse: integer(1, 1 << 30) },
  MAX_CATCH_UP_TICKS: { default: '10', parse: integer(1, 600) },
  HTTP_RATE_LIMIT: { default: '600', parse: integer(1, 1e9) },
  HTTP_IDLE_TIMEOUT_MS: { default: '30000', parse: integer(100, 3600000) },
  HTTP_REQUEST_TIMEOUT_MS: { default: '30000', parse: integer(100, 3600000) },
  SESSION_RATE_LIMIT: { default: '30', parse: integer(1, 1e9) },
  WS_MAX_CONNECTIONS: { default: '10000', parse: integer(1, 1e7) },
  WS_MAX_CONNECTIONS_PER_IP: { default: '50', parse: integer(1, 1e7) },
  WS_MESSAGE_RATE: { default: '100', parse: integer(1, 1e6) },
  WS_MESSAGE_BURST: { default: '200', parse: integer(1, 1e6) },
  WS_HEARTBEAT_MS: { default: '30000', parse: integer(100, 3600000) },
  SHUTDOWN_TIMEOUT_MS: { default: '10000', parse: integer(100, 3600000) },
  TRUST_PROXY: { default: 'false', parse: trustProxy },
  CLIENT_DIR: { default: path.join(ROOT, 'client'), parse: (v) => path.resolve(nonEmpty(v)) },
  // Clustering (server/cluster/): REDIS_URL turns it on; see the README's "Scaling out".
  REDIS_URL: { default: '', parse: redisUrl, secret: true },
  PUBLIC_URL: { default: '', parse: publicUrl },
  LEASE_TTL_MS: { default: '5000', parse: integer(300, 600_000) }
}

/**
 * @typedef {object} Config
 * @property {number} port @property {string} host
 * @property {{ kind: 'sqlite', file: string, busyTimeoutMs: number } | { kind: 'postgres', url: string }} database
 * @property {string} operatorToken @property {boolean} operatorTokenGenerated
 * @property {number} snapshotHz @property {number} startingBalance
 * @property {'snapshot' | 'immediate'} spectatorEvents when the room hears of a drop: with its next snapshot (one frame), or as soon as it is committed (one `events` frame per room per batch)
 * @property {number} minBet @property {number} maxBet @property {string} logLevel
 * @property {number} dropRate drops per second per player (token bucket refill)
 * @property {number} dropBurst token bucket capacity
 * @property {number} dropRatePerIp drops per second from one client IP, all its sessions together (burst: 2 s worth)
 * @property {number} joinRate joins per second per player (burst: 2 s worth)
 * @property {number} joinRatePerIp joins per second from one client IP (burst: 2 s worth)
 * @property {number} maxBallsPerRoom @property {number} wsMaxPayload
 * @property {number} wsSoftBuffer bytes queued on a socket above which snapshots are skipped
 * @property {number} wsHardBuffer bytes queued on a socket above which it is closed
 * @property {number} maxCatchUpTicks @property {number} httpRateLimit per IP per minute
 * @property {number} sessionRateLimit new sessions per IP per minute
 * @property {number} httpIdleTimeoutMs an HTTP connection idle this long is closed (also keep-alive between requests, capped at 5 s)
 * @property {number} httpRequestTimeoutMs a request must arrive whole (headers and body) within this
 * @property {number} wsMaxConnections open WebSockets in total
 * @property {number} wsMaxConnectionsPerIp open WebSockets per client IP
 * @property {number} wsMessageRate frames per second per connection (token bucket refill)
 * @property {number} wsMessageBurst token bucket capacity for frames per connection
 * @property {number} wsHeartbeatMs ping interval; a peer that misses a ping is dropped
 * @property {number} shutdownTimeoutMs bound on a graceful shutdown, after which the process exits anyway
 * @property {false | number | string[]} trustProxy which X-Forwarded-For hops to believe (see trustProxy()) @property {string} clientDir
 * @property {string} redisUrl '' = one process alone; set = clustered (server/cluster/)
 * @property {string} publicUrl how clients reach this process ('' = http://HOST:PORT once listening)
 * @property {number} leaseTtlMs room lease lifetime; a dead process's rooms move after at most this
 */

export class ConfigError extends Error {
  /** @param {string[]} problems */
  constructor (problems) {
    super('invalid configuration:\n  ' + problems.join('\n  '))
    this.name = 'ConfigError'
    this.problems = problems
  }
}

/**
 * Reads and validates the configuration; throws one ConfigError listing
 * every problem, so an operator fixes them all in one go.
 * @param {Record<string, string | undefined>} [env]
 * @returns {Readonly<Config>}
 */
export function loadConfig (env = process.env) {
  const problems = []
  const values = {}
  for (const [name, spec] of Object.entries(VARIABLES)) {
    const raw = env[name] === undefined || env[name] === '' ? spec.default : env[name]
    try {
      values[name] = spec.parse(raw)
    } catch (error) {
      // Secrets are never echoed, even when invalid.
      const shown = spec.secret ? '(value hidden)' : JSON.stringify(env[name])
      problems.push(`${name}=${shown}: ${error.message}`)
    }
  }
  if (problems.length === 0 && values.MAX_BET < values.MIN_BET) problems.push('MAX_BET must be >= MIN_BET')
  if (problems.length === 0 && values.WS_HARD_BUFFER <= values.WS_SOFT_BUFFER) problems.push('WS_HARD_BUFFER must be > WS_SOFT_BUFFER')
  if (problems.length === 0 && values.REDIS_URL && values.DATABASE_URL?.kind !== 'postgres') {
    problems.push('REDIS_URL (clustering) needs DATABASE_URL=postgres://…: the processes share one ledger')
  }
  if (problems.length > 0) throw new ConfigError(problems)

  const generated = values.OPERATOR_TOKEN === ''
  return Object.freeze({
    port: values.PORT,
    host: values.HOST,
    database: withBusyTimeout(values.DATABASE_URL ?? { kind: 'sqlite', file: path.join(ROOT, 'data', 'plinko.sqlite') }, values.SQLITE_BUSY_TIMEOUT_MS),
    operatorToken: generated ? randomToken() : values.OPERATOR_TOKEN,
    operatorTokenGenerated: generated,
    snapshotHz: values.SNAPSHOT_HZ,
    spectatorEvents: values.SPECTATOR_EVENTS,
    startingBalance: values.STARTING_BALANCE,
    minBet: values.MIN_BET,
    maxBet: values.MAX_BET,
    logLevel: values.LOG_LEVEL,
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
    httpIdleTimeoutMs: values.HTTP_IDLE_TIMEOUT_MS,
    httpRequestTimeoutMs: values.HTTP_REQUEST_TIMEOUT_MS,
    sessionRateLimit: values.SESSION_RATE_LIMIT,
    wsMaxConnections: values.WS_MAX_CONNECTIONS,
    wsMaxConnectionsPerIp: values.WS_MAX_CONNECTIONS_PER_IP,
    wsMessageRate: values.WS_MESSAGE_RATE,
    wsMessageBurst: values.WS_MESSAGE_BURST,
    wsHeartbeatMs: values.WS_HEARTBEAT_MS,
    shutdownTimeoutMs: values.SHUTDOWN_TIMEOUT_MS,
    trustProxy: values.TRUST_PROXY,
    clientDir: values.CLIENT_DIR,
    redisUrl: values.REDIS_URL,
    publicUrl: values.PUBLIC_URL,
    leaseTtlMs: values.LEASE_TTL_MS
  })
}

/** SQLite: how long a write waits for another process's write lock before failing with E_UNAVAILABLE. */
function withBusyTimeout (database, busyTimeoutMs) {
  return database.kind === 'sqlite' ? { ...database, busyTimeoutMs } : database
}

/** Names of all variables, for documentation and tests. */
export const CONFIG_VARIABLES = Object.freeze(Object.keys(VARIABLES))

function randomToken () {
  const bytes = new Uint8Array(32)
  globalThis.crypto.getRandomValues(bytes)
  return Buffer.from(bytes).toString('hex')
}

function integer (min, max) {
  return (raw) => {
    if (!/^-?\d+$/.test(raw.trim())) throw new Error(`must be an integer from ${min} to ${max}`)
    const value = Number(raw)
    if (!Number.isSafeInteger(value) || value < min || value > max) throw new Error(`must be an integer from ${min} to ${max}`)
    return value
  }
}

function oneOf (allowed, map = (v) => v) {
  return (raw) => {
    if (!allowed.includes(raw)) throw new Error(`must be one of ${allowed.join(', ')}`)
    return map(raw)
  }
}

function nonEmpty (raw) {
  if (raw.trim() === '') throw new Error('must not be empty')
  return raw
}

function operatorToken (raw) {
  if (raw !== '' && raw.length < 16) throw new Error('must be at least 16 characters (or unset to generate one)')
  return raw
}

/** '' (off) or redis:// / rediss:// */
function redisUrl (raw) {
  if (raw === '') return ''
  if (!/^rediss?:\/\//.test(raw)) throw new Error('must be redis://[user:password@]host:port[/db] or rediss://…')
  try { new URL(raw) } catch { throw new Error('is not a valid redis:// URL') } // eslint-disable-line no-new
  return raw
}

const PROXY_KEYWORDS = ['loopback', 'linklocal', 'uniquelocal']

/**
 * Which X-Forwarded-For hops to believe: 'false' (none: the socket's peer is
 * the client), a number N of proxies in front of the server (the client is
 * the Nth address from the right: what the nearest proxy saw), or the
 * proxies' addresses (IPs, CIDR subnets, or loopback / linklocal /
 * uniquelocal, comma-separated). 'true' is refused: it believes every hop,
 * and the client writes the left-most one itself.
 */
function trustProxy (raw) {
  const value = raw.trim()
  if (value === 'false') return false
  if (value === 'true') throw new Error('"true" would believe the client\'s own X-Forwarded-For (its left-most address); give the number of proxies in front of the server (e.g. 1) or their addresses (e.g. 127.0.0.1, 10.0.0.0/8, loopback)')
  if (/^\d+$/.test(value)) {
    const hops = Number(value)
    if (hops < 1 || hops > 10) throw new Error('as a number of proxy hops must be from 1 to 10')
    return hops
  }
  const list = value.split(',').map((entry) => entry.trim())
  for (const entry of list) {
    const [address, prefix, extra] = entry.split('/')
    const family = net.isIP(address)
    const validPrefix = prefix === undefined || (/^\d+$/.test(prefix) && Number(prefix) <= (family === 6 ? 128 : 32))
    if (PROXY_KEYWORDS.includes(entry) || (family !== 0 && validPrefix && extra === undefined)) continue
    throw new Error(`must be false, a number of proxy hops, or proxy addresses (IPs, subnets, ${PROXY_KEYWORDS.join(', ')}); "${entry}" is none of them`)
  }
  return list
}

/** '' or an absolute http(s) URL without a trailing slash (a path prefix is allowed: http://lb/n/node1). */
function publicUrl (raw) {
  if (raw === '') return ''
  let url
  try { url = new URL(raw) } catch { throw new Error('must be an absolute http:// or https:// URL') }
  if (url.protocol !== 'http:' && url.protocol !== 'https:') throw new Error('must be an absolute http:// or https:// URL')
  return raw.replace(/\/+$/, '')
}

/** '' → default SQLite file; sqlite:PATH; postgres://… or postgresql://… */
function databaseUrl (raw) {
  if (raw === '') return undefined
  if (raw.startsWith('sqlite:')) {
    const file = raw.slice('sqlite:'.length)
    if (file === '') throw new Error('sqlite: needs a file path, e.g. sqlite:./data/plinko.sqlite')
    return { kind: 'sqlite', file: file === ':memory:' ? file : path.resolve(file) }
  }
  if (/^postgres(ql)?:\/\//.test(raw)) {
    try { new URL(raw) } catch { throw new Error('is not a valid postgres:// URL') } // eslint-disable-line no-new
    return { kind: 'postgres', url: raw }
  }
  throw new Error('must be sqlite:PATH or postgres://user:password@host:port/database')
}
