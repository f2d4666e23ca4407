import { TICK_P99_GOAL_S, TICK_PERIOD_S } from './run-analysis.js'

/**
 * The run's report.md: the verdict first, then what the players saw (k6),
 * what the server measured in the steady window (/metrics), the CPU
 * profile if one was taken, and the chart.
 * @param {object} run
 * @param {string} run.title
 * @param {string} run.command
 * @param {Record<string, string>} run.machine
 * @param {Record<string, string | number>} run.settings
 * @param {ReturnType<import('./run-analysis.js').analyzeServerSamples>} run.server
 * @param {any} run.k6 k6 --summary-export JSON (null if missing)
 * @param {number | null} run.k6ExitCode
 * @param {{ code: number | null, signal: string | null } | null} run.serverExit
 * @param {{ file: string, summary: ReturnType<import('./cpu-profile-summary.js').summarizeCpuProfile> } | null} run.profile
 * @param {string[]} run.files
 */
export function renderReport (run) {
  const failedThresholds = failedK6Thresholds(run.k6)
  return [
    ...headerSection(run, failedThresholds),
    ...verdictSection(run, failedThresholds),
    ...playersSection(run.k6),
    ...serverSection(run),
    '![time series](chart.svg)', '',
    ...profileSection(run.profile),
    '## Files', '', ...run.files.map((file) => `- \`${file}\``), ''
  ].join('\n')
}

/** The k6 thresholds that failed, as `metric expression`. */
function failedK6Thresholds (k6) {
  return Object.entries(k6?.metrics ?? {}).flatMap(([name, metric]) =>
    Object.entries(metric.thresholds ?? {}).filter(([, failed]) => failed).map(([expression]) => `${name} ${expression}`))
}

/** A k6 counter's count (null when k6 did not report it). */
const countOf = (k6, name) => k6?.metrics?.[name]?.count ?? null

/** The title with PASS or FAIL, the command, the machine and the settings. */
function headerSection (run, failedThresholds) {
  const passed = run.k6ExitCode === 0 && failedThresholds.length === 0
  return [
    `# ${run.title}: ${passed ? 'PASS' : 'FAIL'}`, '',
    '```sh', run.command, '```', '',
    table(['machine', ''], Object.entries(run.machine)), '',
    table(['setting', 'value'], Object.entries(run.settings).map(([k, v]) => [k, String(v)])), ''
  ]
}

/** Each criterion of a passing run, measured against its goal. */
function verdictSection (run, failedThresholds) {
  const { server, k6 } = run
  const count = (name) => countOf(k6, name)
  const tickOk = server.tick?.within8ms !== null && server.tick?.within8ms !== undefined ? server.tick.within8ms >= 0.99 : null
  return ['## Verdict', '', table(['criterion', 'measured', 'goal', ''], [
    ['k6 thresholds', failedThresholds.length === 0 ? 'all passed' : failedThresholds.join('; '), 'all pass', mark(failedThresholds.length === 0 && k6 !== null)],
    ['k6 exit code', String(run.k6ExitCode), '0', mark(run.k6ExitCode === 0)],
    ['errors seen by players', fmt(count('plinko_errors')), '0', mark(count('plinko_errors') === 0)],
    ['unsettled drops', fmt(count('unsettled_drops')), '0', mark(count('unsettled_drops') === 0)],
    ['balance mismatches', fmt(count('balance_mismatches')), '0', mark(count('balance_mismatches') === 0)],
    ['drops settled / sent', `${fmt(count('drops_settled'))} / ${fmt(count('drops_sent'))}`, 'equal', mark(count('drops_settled') !== null && count('drops_settled') === count('drops_sent'))],
    ['tick duration p99 (steady)', msText(server.tick?.p99), `< ${TICK_P99_GOAL_S * 1000} ms`, mark(tickOk)],
    ['ticks ≤ 8 ms (steady)', pct(server.tick?.within8ms), '≥ 99%', mark(tickOk)],
    ['tick lag p99 (steady): every tick starts within one period', msText(server.tickLag?.p99), `< ${fmt(TICK_PERIOD_S * 1000, 1)} ms`, mark(server.tickLag?.p99 != null ? server.tickLag.p99 < TICK_PERIOD_S : null)],
    ['ticks dropped (steady)', fmt(server.tick?.dropped), '0', mark(server.tick ? server.tick.dropped === 0 : null)],
    ['server exit', run.serverExit ? `${run.serverExit.code ?? run.serverExit.signal}` : 'not started by the run', '0', mark(run.serverExit ? run.serverExit.code === 0 : null)]
  ]), '']
}

/** What k6 measured: latencies, traffic per kind, errors by code, players and drops. */
function playersSection (k6) {
  const lines = ['## What the players saw (k6)', '']
  if (!k6) return [...lines, 'No k6 summary (k6 did not finish).', '']
  const m = k6.metrics ?? {}
  const count = (name) => countOf(k6, name)
  lines.push(table(['metric', 'p50', 'p90', 'p99', 'max', 'count'], [
    trendRow('drop → dropped (ack) ms', m.drop_ack_ms),
    trendRow('drop → settled ms (with flight)', m.drop_settled_ms),
    trendRow('drop → settled minus flight ms', m.drop_settle_overhead_ms),
    trendRow('snapshot interval ms (sampled)', m.snapshot_interval_ms),
    trendRow('snapshot jitter ms (sampled)', m.snapshot_jitter_ms),
    trendRow('messages/s per client', m.client_msgs_per_s, 1),
    trendRow('bytes/s per client (payload)', m.client_bytes_per_s, 0),
    trendRow('WebSocket connect ms', m.ws_connecting),
    trendRow('POST /api/session ms', m.http_req_duration)
  ]), '')
  const kinds = ['json', 'snapshot', 'drop_events'].map((kind) => [kind, fmt(m[`messages_received{kind:${kind}}`]?.count), fmt(m[`bytes_received{kind:${kind}}`]?.count)])
  if (kinds.some(([, a]) => a !== '–')) lines.push(table(['received', 'messages', 'bytes'], kinds), '')
  const errorCodes = Object.entries(m).filter(([name, metric]) => name.startsWith('plinko_errors{code:') && metric.count > 0)
    .map(([name, metric]) => [name.slice('plinko_errors{code:'.length, -1), String(metric.count)])
  if (errorCodes.length) lines.push('Errors seen by players, by code:', '', table(['code', 'count'], errorCodes), '')
  lines.push(`Players (VUs): ${fmt(m.vus_max?.max ?? m.vus_max?.value)}; drops sent ${fmt(count('drops_sent'))}, settled ${fmt(count('drops_settled'))}; WebSocket sessions ${fmt(count('ws_sessions'))}.`, '')
  return lines
}

/** What /metrics showed in the steady window, and the errors the server returned. */
function serverSection ({ server, machine }) {
  const lines = ['## What the server measured (GET /metrics, steady window)', '']
  if (!server.window) return [...lines, 'No steady window: the server never reported connected players.', '']
  const w = server.window
  lines.push(`Steady window: t = ${w.from.toFixed(0)}–${w.to.toFixed(0)} s (${w.seconds.toFixed(0)} s) of the run, every player connected.`, '')
  lines.push(table(['figure', 'value'], [
    ['connected players (mean / peak)', `${fmt(server.clients.mean, 0)} / ${fmt(server.clients.peak)}`],
    ['rooms', fmt(server.rooms)],
    ['balls in flight (mean)', fmt(server.ballsInFlight, 0)],
    ['tick duration p50 / p99 / max', `${msText(server.tick.p50)} / ${msText(server.tick.p99)} / ≤ ${msText(server.tick.max)}`],
    ['ticks ≤ 8 ms', pct(server.tick.within8ms)],
    ['ticks per second / dropped', `${fmt(server.tick.perSecond, 1)} / ${fmt(server.tick.dropped)}`],
    ['tick lag p50 / p99', `${msText(server.tickLag.p50)} / ${msText(server.tickLag.p99)}`],
    ['event-loop delay p99 (median of scrapes / worst scrape) / max', `${msText(server.eventLoop.p99Median)} / ${msText(server.eventLoop.p99Max)} / ${msText(server.eventLoop.max)}`],
    ['group commit p50 / p99, commits per second', `${msText(server.commit.p50)} / ${msText(server.commit.p99)}, ${fmt(server.commit.perSecond, 1)}`],
    ['CPU: server / k6 / other processes / whole machine (100% = one core)', `${pct(server.cpu.server)} / ${pct(server.cpu.k6)} / ${pct(server.cpu.others)} / ${pct(server.cpu.machine)} of ${machine.cores * 100}%`],
    ['RSS: before players / steady', `${mb(server.memory.rssBaseline)} / ${mb(server.memory.rss)}`],
    ['RSS per connected player', kb(server.memory.rssPerClient)],
    ['JS heap used: before / steady, per player', `${mb(server.memory.heapBaseline)} / ${mb(server.memory.heap)}, ${kb(server.memory.heapPerClient)}`],
    ['k6 RSS', mb(server.k6Rss)],
    ['bytes out per second (all / per player)', `${fmt(server.traffic.bytesOutPerSecond, 0)} / ${fmt(server.traffic.bytesPerClientPerSecond, 0)}`],
    ['messages out per second (all / per player)', `${fmt(server.traffic.messagesOutPerSecond, 0)} / ${fmt(server.traffic.messagesPerClientPerSecond, 1)}`],
    ['drops / settles per second', `${fmt(server.traffic.dropsPerSecond, 1)} / ${fmt(server.traffic.settlesPerSecond, 1)}`],
    ['snapshots skipped (backpressure) / slow consumers closed', `${fmt(server.traffic.snapshotsSkipped)} / ${fmt(server.traffic.slowConsumersClosed)}`]
  ]), '')
  const serverErrors = Object.entries(server.serverErrors ?? {})
  lines.push(serverErrors.length ? `Errors the server returned (whole run): ${serverErrors.map(([code, n]) => `${code} ${n}`).join(', ')}.` : 'Errors the server returned (whole run): none.', '')
  return lines
}

/** The server's CPU profile, if one was taken: self time by area, top functions. */
function profileSection (profile) {
  if (!profile) return []
  const p = profile.summary
  return [
    '## CPU profile of the server', '',
    `\`${profile.file}\` (open in Chrome DevTools → Performance, or speedscope). Steady window only: ${fmt(p.totalMs / 1000, 1)} s of samples.`, '',
    'Self time by area:', '', table(['area', 'ms', 'share'], p.areas.slice(0, 15).map((a) => [a.area, fmt(a.ms, 0), pct(a.share)])), '',
    'Top functions by self time:', '', table(['function', 'area', 'ms', 'share'], p.selfTop.map((f) => [`\`${f.name}\``, f.area, fmt(f.ms, 0), pct(f.share)])), '',
    'Our functions by inclusive time:', '', table(['function', 'ms', 'share'], p.inclusiveTop.map((f) => [`\`${f.name}\``, fmt(f.ms, 0), pct(f.share)])), ''
  ]
}

function table (header, rows) {
  const escape = (cell) => String(cell).replaceAll('|', '\\|')
  return [`| ${header.join(' | ')} |`, `| ${header.map(() => '---').join(' | ')} |`, ...rows.map((row) => `| ${row.map(escape).join(' | ')} |`)].join('\n')
}

function trendRow (label, metric, digits = 1) {
  if (!metric) return [label, '–', '–', '–', '–', '–']
  return [label, fmt(metric.med, digits), fmt(metric['p(90)'], digits), fmt(metric['p(99)'], digits), fmt(metric.max, digits), fmt(metric.count)]
}

function mark (ok) {
  return ok === null || ok === undefined ? '' : ok ? '✅' : '❌'
}

export function fmt (value, digits = 0) {
  if (value === null || value === undefined || Number.isNaN(value)) return '–'
  if (value === Infinity) return '∞'
  return Number(value).toLocaleString('en-US', { minimumFractionDigits: digits, maximumFractionDigits: digits })
}

function msText (seconds) {
  if (seconds === null || seconds === undefined) return '–'
  if (seconds === Infinity) return '> 50 ms'
  return `${fmt(seconds * 1000, 2)} ms`
}

function pct (fraction) {
  return fraction === null || fraction === undefined ? '–' : `${fmt(fraction * 100, 1)}%`
}

function mb (bytes) {
  return bytes === null || bytes === undefined ? '–' : `${fmt(bytes / 2 ** 20, 1)} MB`
}

function kb (bytes) {
  return bytes === null || bytes === undefined ? '–' : `${fmt(bytes / 1024, 1)} KB`
}
