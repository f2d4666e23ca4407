/**
 * Arguments of `npm run loadtest -- …` (loadtest/run.js).
 */

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
  --env KEY=VALUE        extra environment for the server (repeatable)
  -e KEY=VALUE           extra k6 variable, e.g. -e SETTLE_P99_MS=250 (repeatable)
  --profile              run the server under node --cpu-prof; the profile and its summary go in the report
  --pin                  pin the server to CPU 0 and k6 to the other CPUs (taskset)
  --sample-interval TIME how often /metrics is read (default 1s)
  --out DIR              report folder (default loadtest/results/<timestamp>)
  -h, --help

TARGET_URL=http://127.0.0.1:PORT runs against a server already running there
(loopback only) instead of starting one; --profile, --pin and --env then do not apply.
Times: 90s, 1500ms, 10m, 1h. Exit code: 0 when every k6 threshold passed.`

/**
 * @param {string | undefined} value
 * @returns {number} seconds
 */
export function parseDuration (value) {
  const match = /^(\d+(?:\.\d+)?)(ms|s|m|h)?$/.exec(String(value ?? '').trim())
  if (!match) throw new UsageError(`not a duration: ${value} (use 90s, 1500ms, 10m, 1h)`)
  return Number(match[1]) * { ms: 0.001, s: 1, m: 60, h: 3600 }[match[2] ?? 's']
}

export class UsageError extends Error {}

/**
 * @param {string[]} argv
 * @returns {{ help: boolean, scenario: string, vus: number, rooms: number, durationS?: number,
 *   dropIntervalS: number, rampS?: number, leaveS?: number, drainS?: number, bet?: number,
 *   snapshotHz?: number, serverEnv: Record<string, string>, k6Env: Record<string, string>,
 *   profile: boolean, pin: boolean, sampleIntervalS: number, out?: string }}
 */
export function parseArgs (argv) {
  const options = { help: false, scenario: 'players', vus: 50, rooms: 10, dropIntervalS: 2, serverEnv: {}, k6Env: {}, profile: false, pin: false, sampleIntervalS: 1 }
  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i]
    const [flag, inline] = arg.startsWith('--') && arg.includes('=') ? [arg.slice(0, arg.indexOf('=')), arg.slice(arg.indexOf('=') + 1)] : [arg, undefined]
    const value = () => {
      if (inline !== undefined) return inline
      if (i + 1 >= argv.length) throw new UsageError(`${flag} needs a value`)
      return argv[++i]
    }
    switch (flag) {
      case '-h': case '--help': options.help = true; break
      case '--scenario': options.scenario = value(); break
      case '--vus': options.vus = positiveInteger(flag, value()); break
      case '--rooms': options.rooms = positiveInteger(flag, value()); break
      case '--duration': options.durationS = parseDuration(value()); break
      case '--drop-interval': options.dropIntervalS = parseDuration(value()); break
      case '--ramp': options.rampS = parseDuration(value()); break
      case '--leave': options.leaveS = parseDuration(value()); break
      case '--drain': options.drainS = parseDuration(value()); break
      case '--bet': options.bet = positiveInteger(flag, value()); break
      case '--snapshot-hz': options.snapshotHz = positiveInteger(flag, value()); break
      case '--env': Object.assign(options.serverEnv, keyValue(flag, value())); break
      case '-e': Object.assign(options.k6Env, keyValue(flag, value())); break
      case '--profile': options.profile = true; break
      case '--pin': options.pin = true; break
      case '--sample-interval': options.sampleIntervalS = parseDuration(value()); break
      case '--out': options.out = value(); break
      default: throw new UsageError(`unknown argument ${arg}`)
    }
  }
  if (!SCENARIOS.includes(options.scenario)) throw new UsageError(`--scenario must be one of ${SCENARIOS.join(', ')}`)
  if (options.durationS !== undefined && options.durationS <= 0) throw new UsageError('--duration must be positive')
  if (options.sampleIntervalS < 0.1) throw new UsageError('--sample-interval must be at least 100ms')
  return options
}

function positiveInteger (flag, raw) {
  const value = Number(raw)
  if (!Number.isInteger(value) || value < 1) throw new UsageError(`${flag} must be a positive integer, got ${raw}`)
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
