/**
 * Scenario settings for the k6 scripts, read from environment variables
 * (`k6 run -e VUS=2000 …`; loadtest/run.js passes them), and the guard that
 * keeps every script on this machine: BASE_URL must name localhost,
 * 127.0.0.1 or [::1], or the script refuses to start.
 *
 *   variable        default                  meaning
 *   BASE_URL        http://127.0.0.1:8080    the server (loopback only)
 *   VUS             50                       virtual players
 *   DURATION        60s                      steady phase: every player connected and dropping
 *   RAMP            10s                      players connect spread over this time
 *   LEAVE           0s                       players leave spread over this time (spike.js: 5s)
 *   ROOMS           10                       rooms the players are spread over (player i → room i mod ROOMS)
 *   DROP_INTERVAL   2s                       each player drops one ball this often (0: never)
 *   BET             10                       credits per drop
 *   DRAIN           20s                      after the steady phase, how long a player waits for its last settles
 *   JITTER_SAMPLE   5                        record one snapshot interval in this many (k6 CPU is shared with the server)
 *   SETTLE_P99_MS   500                      threshold: p99 of (drop→settled − ball flight time)
 *   ACK_P99_MS      500                      threshold: p99 of drop→dropped
 *   JITTER_P99_MS   150                      threshold: p99 of snapshot jitter
 *   DELIVERY        snapshots                the players' join.delivery: snapshots (positions) or seeds (drop-events frames only)
 *   BREAKDOWN       (unset)                  1: also summarize errors by code and traffic by kind
 */

import { ERROR_CODES } from '../../server/errors.js'
import { DELIVERY_MODES } from '../../protocol/client-messages.js'

/** Error codes the players count besides the server's own (see player.js). */
const CLIENT_ERROR_CODES = ['X_UNEXPECTED_SNAPSHOT', 'X_BAD_FRAME', 'X_BALANCE_MISMATCH', 'X_BAD_PAYOUT', 'X_UNKNOWN_DROP', 'X_UNKNOWN_SETTLE', 'X_JOIN_TIMEOUT', 'X_BAD_JSON',
  'WS_ERROR', 'WS_CLOSE_1001', 'WS_CLOSE_1006', 'WS_CLOSE_1008', 'WS_CLOSE_1011', 'WS_CLOSE_1013', 'WS_CLOSE_4401',
  'HTTP_0', 'HTTP_429', 'HTTP_500', 'HTTP_503']

const LOOPBACK = /^(https?):\/\/(localhost|127\.0\.0\.1|\[::1\])(:\d{1,5})?\/?$/
/** An E_WRONG_NODE `owner`: a loopback URL, possibly with a path (a process behind a proxy, /n/1). */
const LOOPBACK_OWNER = /^(https?):\/\/(localhost|127\.0\.0\.1|\[::1\])(:\d{1,5})?(\/[A-Za-z0-9._~\/-]*)?$/

/**
 * The socket URL of an E_WRONG_NODE `owner`, or null when it is not on
 * loopback: the scripts never send traffic anywhere else.
 * @param {unknown} owner
 * @returns {string | null}
 */
export function ownerSocketUrl (owner) {
  const match = typeof owner === 'string' ? LOOPBACK_OWNER.exec(owner) : null
  if (!match) return null
  const path = (match[4] ?? '').replace(/\/+$/, '')
  return `${match[1] === 'https' ? 'wss' : 'ws'}://${match[2]}${match[3] ?? ''}${path}/ws`
}

/**
 * @param {string | undefined} value `90`, `90s`, `1500ms`, `10m`, `1h`
 * @param {number} fallback seconds
 * @returns {number} seconds
 */
export function parseSeconds (value, fallback) {
  if (value === undefined || value === '') return fallback
  const match = /^(\d+(?:\.\d+)?)(ms|s|m|h)?$/.exec(String(value).trim())
  if (!match) throw new Error(`not a duration: ${value} (use 90s, 1500ms, 10m, 1h)`)
  const scale = { ms: 0.001, s: 1, m: 60, h: 3600 }[match[2] ?? 's']
  return Number(match[1]) * scale
}

function positiveInteger (name, fallback) {
  const raw = __ENV[name]
  if (raw === undefined || raw === '') return fallback
  const value = Number(raw)
  if (!Number.isInteger(value) || value < 1) throw new Error(`${name} must be a positive integer, got ${raw}`)
  return value
}

function numberVar (name, fallback) {
  const raw = __ENV[name]
  if (raw === undefined || raw === '') return fallback
  const value = Number(raw)
  if (!Number.isFinite(value) || value < 0) throw new Error(`${name} must be a non-negative number, got ${raw}`)
  return value
}

/**
 * The base URL, refused unless it is on loopback. @returns {string} without a trailing slash
 */
export function loopbackBaseUrl (raw = __ENV.BASE_URL || 'http://127.0.0.1:8080') {
  const match = LOOPBACK.exec(raw)
  if (!match) throw new Error(`BASE_URL ${raw} is not on this machine: load tests only target http://localhost, 127.0.0.1 or [::1]`)
  return raw.replace(/\/$/, '')
}

/**
 * Everything a scenario needs, with its own defaults for duration and ramp.
 * @param {{ duration?: string, ramp?: string, leave?: string, vus?: number }} defaults
 */
export function readScenarioConfig (defaults = {}) {
  const baseUrl = loopbackBaseUrl()
  const config = {
    baseUrl,
    wsUrl: baseUrl.replace(/^http/, 'ws') + '/ws',
    vus: positiveInteger('VUS', defaults.vus ?? 50),
    durationS: parseSeconds(__ENV.DURATION, parseSeconds(defaults.duration, 60)),
    rampS: parseSeconds(__ENV.RAMP, parseSeconds(defaults.ramp, 10)),
    leaveS: parseSeconds(__ENV.LEAVE, parseSeconds(defaults.leave, 0)),
    rooms: positiveInteger('ROOMS', 10),
    dropIntervalMs: parseSeconds(__ENV.DROP_INTERVAL, 2) * 1000,
    bet: positiveInteger('BET', 10),
    drainS: parseSeconds(__ENV.DRAIN, 20),
    jitterSampleEvery: positiveInteger('JITTER_SAMPLE', 5),
    settleP99Ms: numberVar('SETTLE_P99_MS', 500),
    ackP99Ms: numberVar('ACK_P99_MS', 500),
    jitterP99Ms: numberVar('JITTER_P99_MS', 150),
    delivery: __ENV.DELIVERY || 'snapshots'
  }
  if (config.durationS <= 0) throw new Error('DURATION must be positive')
  if (!DELIVERY_MODES.includes(config.delivery)) throw new Error(`DELIVERY must be one of ${DELIVERY_MODES.join(', ')}`)
  return config
}

/**
 * k6 options for a scenario where each VU is one player for the whole run
 * (one iteration), bounded by maxDuration however the server behaves.
 * @param {ReturnType<typeof readScenarioConfig>} config
 * @param {string} name
 */
export function playerScenarioOptions (config, name) {
  const lifetimeS = config.rampS + config.durationS + config.leaveS + config.drainS
  return {
    scenarios: {
      [name]: {
        executor: 'per-vu-iterations',
        vus: config.vus,
        iterations: 1,
        maxDuration: `${Math.ceil(lifetimeS + 60)}s`,
        gracefulStop: '10s'
      }
    },
    setupTimeout: '60s',
    teardownTimeout: '60s',
    // Every WebSocket URL carries a token: name it, so per-URL time series stay one.
    systemTags: ['status', 'method', 'name', 'scenario', 'expected_response', 'error_code'],
    summaryTrendStats: ['avg', 'min', 'med', 'p(90)', 'p(99)', 'max', 'count'],
    thresholds: {
      plinko_errors: ['count==0'],
      unsettled_drops: ['count==0'],
      balance_mismatches: ['count==0'],
      checks: ['rate==1'],
      drops_settled: ['count>0'],
      drop_settle_overhead_ms: [`p(99)<${config.settleP99Ms}`],
      drop_ack_ms: [`p(99)<${config.ackP99Ms}`],
      // Seeds mode has no snapshots to time: a snapshot frame there is an error (X_UNEXPECTED_SNAPSHOT) instead.
      ...(config.delivery === 'seeds' ? { drop_events_received: ['count>0'] } : { snapshot_jitter_ms: [`p(99)<${config.jitterP99Ms}`] }),
      ...(__ENV.BREAKDOWN ? breakdown() : {})
    }
  }
}

/**
 * With BREAKDOWN=1 (run.js sets it), always-true thresholds on tagged
 * sub-metrics: k6 exports a sub-metric in its summary only when a threshold
 * names it, and the report wants errors by code and traffic by kind.
 * (plinko_errors itself counts every code.)
 */
function breakdown () {
  const entries = {}
  for (const code of [...Object.keys(ERROR_CODES), ...CLIENT_ERROR_CODES]) entries[`plinko_errors{code:${code}}`] = ['count>=0']
  for (const kind of ['json', 'snapshot', 'drop_events']) {
    entries[`messages_received{kind:${kind}}`] = ['count>=0']
    entries[`bytes_received{kind:${kind}}`] = ['count>=0']
  }
  return entries
}
