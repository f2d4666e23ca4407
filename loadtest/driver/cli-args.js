/**
 * Arguments of `npm run loadtest -- …` (loadtest/run.js), read with
 * node:util parseArgs like the `plinko` CLI's (cli/command-line.js).
 */
import { parseCommandLine } from '../../cli/command-line.js'
import { UsageError } from '../../cli/usage-error.js'
import { DELIVERY_MODES } from '../../protocol/client-messages.js'

export { UsageError }

export const SCENARIOS = ['players', 'spike', 'soak']

export const USAGE = `usage: npm run loadtest -- [options]

  --scenario NAME        players (default), spike or soak
  --vus N                virtual players (default 50)
  --duration TIME        steady phase (default: players 60s, spike 20s, soak 10m)
  --rooms N              rooms the players are spread over (default 10)
  --drop-interval TIME   one drop per player this often (default 2s; 0 = never)
  --ramp TIME            players connect spread over this time (default: players 10s, spike 5s, soak 30s)
  --leave TIME           players leave spread over this time (spike: 5s)
  --drain TIME           how long players wait for their last settles (default 20s)
  --bet N                credits per drop (default 10)
  --snapshot-hz N        the server's SNAPSHOT_HZ (default: the server's, 20)
  --delivery MODE        the players' join.delivery: snapshots (default) or seeds
  --env KEY=VALUE        extra environment for the server (repeatable)
  -e KEY=VALUE           extra k6 variable, e.g. -e SETTLE_P99_MS=250 (repeatable)
  --profile              run the server under node --cpu-prof; the profile and its summary go in the report
  --pin                  pin the server to CPU 0 and k6 to the other CPUs (taskset)
  --sample-interval TIME how often /metrics is read (default 1s)
  --out DIR              report folder (default loadtest/results/<timestamp>)
  -h, --help

TARGET_URL=http://127.0.0.1:PORT runs against a server already running there
(loopback only) instead of starting one; --profile, --pin and --env then do not apply.
Times: 90s, 1500ms, 10m, 1h. An option given twice keeps its last value.
Exit code: 0 when every k6 threshold passed, 2 for a bad command line.`

/**
 * @param {string | undefined} value
 * @param {string} [name] the option it was given to, for the message
 * @returns {number} seconds
 */
export function parseDuration (value, name) {
  const match = /^(\d+(?:\.\d+)?)(ms|s|m|h)?$/.exec(String(value ?? '').trim())
  if (!match) throw new UsageError(`not a duration: ${value}${name ? ` for --${name}` : ''} (use 90s, 1500ms, 10m, 1h)`)
  return Number(match[1]) * { ms: 0.001, s: 1, m: 60, h: 3600 }[match[2] ?? 's']
}

/** The options, as node:util parseArgs reads them (cli/command-line.js adds the project's errors). */
const OPTIONS = {
  help: { type: 'boolean', short: 'h' },
  scenario: { type: 'string', default: 'players' },
  vus: { type: 'string' },
  duration: { type: 'string' },
  rooms: { type: 'string' },
  'drop-interval': { type: 'string' },
  ramp: { type: 'string' },
  leave: { type: 'string' },
  drain: { type: 'string' },
  bet: { type: 'string' },
  'snapshot-hz': { type: 'string' },
  delivery: { type: 'string' },
  env: { type: 'string', multiple: true, default: [] },
  e: { type: 'string', multiple: true, default: [] },
  profile: { type: 'boolean', default: false },
  pin: { type: 'boolean', default: false },
  'sample-interval': { type: 'string' },
  out: { type: 'string' }
}

/**
 * An option given twice takes its last value (`npm run loadtest:smoke --
 * --vus 100` overrides the script's own `--vus 50`); --env and -e add up.
 * @param {string[]} argv
 * @returns {{ help: boolean, scenario: string, vus: number, rooms: number, durationS?: number,
 *   dropIntervalS: number, rampS?: number, leaveS?: number, drainS?: number, bet?: number,
 *   snapshotHz?: number, delivery: 'snapshots' | 'seeds', serverEnv: Record<string, string>, k6Env: Record<string, string>,
 *   profile: boolean, pin: boolean, sampleIntervalS: number, out?: string }}
 */
export function parseArgs (argv) {
  const values = parseCommandLine(argv, OPTIONS, { repeated: 'last' })
  if (values.help) return { ...parseArgs([]), help: true }
  const optional = (name, parse) => values[name] === undefined ? undefined : parse(values[name], name)
  const options = {
    help: false,
    scenario: values.scenario,
    vus: optional('vus', positiveInteger) ?? 50,
    rooms: optional('rooms', positiveInteger) ?? 10,
    durationS: optional('duration', parseDuration),
    dropIntervalS: optional('drop-interval', parseDuration) ?? 2,
    rampS: optional('ramp', parseDuration),
    leaveS: optional('leave', parseDuration),
    drainS: optional('drain', parseDuration),
    bet: optional('bet', positiveInteger),
    snapshotHz: optional('snapshot-hz', positiveInteger),
    delivery: optional('delivery', deliveryMode) ?? 'snapshots',
    serverEnv: Object.assign({}, ...values.env.map((pair) => keyValue('--env', pair))),
    k6Env: Object.assign({}, ...values.e.map((pair) => keyValue('-e', pair))),
    profile: values.profile,
    pin: values.pin,
    sampleIntervalS: optional('sample-interval', parseDuration) ?? 1,
    out: values.out
  }
  for (const [key, value] of Object.entries(options)) if (value === undefined) delete options[key]
  if (!SCENARIOS.includes(options.scenario)) throw new UsageError(`--scenario must be one of ${SCENARIOS.join(', ')}`)
  if (options.durationS !== undefined && options.durationS <= 0) throw new UsageError('--duration must be positive')
  if (options.sampleIntervalS < 0.1) throw new UsageError('--sample-interval must be at least 100ms')
  return options
}

/** A `join.delivery` given as --NAME, or a UsageError. @param {string} raw @param {string} name @returns {'snapshots' | 'seeds'} */
export function deliveryMode (raw, name) {
  if (!DELIVERY_MODES.includes(raw)) throw new UsageError(`--${name} must be one of ${DELIVERY_MODES.join(', ')}, got ${raw}`)
  return /** @type {'snapshots' | 'seeds'} */ (raw)
}

/** A whole number ≥ 1 given as --NAME, or a UsageError. @param {string} raw @param {string} name */
export function positiveInteger (raw, name) {
  const value = Number(raw)
  if (!Number.isInteger(value) || value < 1) throw new UsageError(`--${name} must be a positive integer, got ${raw}`)
  return value
}

function keyValue (flag, raw) {
  const match = /^([A-Za-z_][A-Za-z0-9_]*)=(.*)$/s.exec(raw)
  if (!match) throw new UsageError(`${flag} needs KEY=VALUE, got ${raw}`)
  return { [match[1]]: match[2] }
}

const LOOPBACK_HOSTS = new Set(['localhost', '127.0.0.1', '[::1]', '::1'])

/**
 * TARGET_URL, refused unless it is an http(s) URL on loopback.
 * @param {string} raw @returns {string} origin, without a trailing slash
 */
export function loopbackTarget (raw) {
  let url
  try { url = new URL(raw) } catch { throw new UsageError(`TARGET_URL ${raw} is not a URL`) }
  if (!['http:', 'https:'].includes(url.protocol) || !LOOPBACK_HOSTS.has(url.hostname) || url.username || url.password || (url.pathname !== '/' && url.pathname !== '')) {
    throw new UsageError(`TARGET_URL ${raw} is not on this machine: load tests only target http://localhost, 127.0.0.1 or [::1] (origin only)`)
  }
  return url.origin
}
