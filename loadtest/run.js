#!/usr/bin/env node
/**
 * `npm run loadtest -- --vus 2000 --duration 60s [--rooms 100] [--drop-interval 2s] [--scenario players|spike|soak]`
 *
 * Starts the game server (a child process on 127.0.0.1 with a fresh SQLite
 * ledger in a temp folder) unless TARGET_URL names one already running on
 * loopback, runs a k6 scenario against it, reads the server's GET /metrics
 * every second while it runs, and writes a report (report.md, chart.svg,
 * the samples and k6's summary) to loadtest/results/<timestamp>/. Exits
 * non-zero when a k6 threshold fails, k6 does not finish, or the server
 * dies. `--help` lists every option.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import readline from 'node:readline'
import { spawn } from 'node:child_process'
import { fileURLToPath } from 'node:url'
import { parseArgs, loopbackTarget, USAGE } from './driver/cli-args.js'
import { optionsOrExit } from '../cli/usage-error.js'
import { k6Binary, k6VersionOf } from './driver/k6-binary.js'
import { startServer } from './driver/server-process.js'
import { MetricsSampler } from './driver/metrics-sampler.js'
import { analyzeServerSamples, TICK_P99_GOAL_S } from './driver/run-analysis.js'
import { renderChart } from './driver/svg-chart.js'
import { renderReport, fmt } from './driver/report-markdown.js'
import { summarizeCpuProfile } from './driver/cpu-profile-summary.js'

const HERE = path.dirname(fileURLToPath(import.meta.url))
const BASELINE_MS = 3000
const AFTER_MS = 2000

const options = optionsOrExit(parseArgs, process.argv.slice(2), USAGE)

let target = null
let k6
try {
  if (process.env.TARGET_URL) target = loopbackTarget(process.env.TARGET_URL)
  k6 = k6Binary()
} catch (error) {
  console.error(error.message)
  process.exit(2)
}

const stamp = new Date().toISOString().replace(/[:.]/g, '-').replace(/-\d{3}Z$/, 'Z')
const outDir = path.resolve(options.out ?? path.join(HERE, 'results', `${stamp}-${options.scenario}-${options.vus}`))
fs.mkdirSync(outDir, { recursive: true })
const command = `${target ? `TARGET_URL=${target} ` : ''}npm run loadtest -- ${process.argv.slice(2).join(' ')}`.trim()
const cpuCount = os.availableParallelism?.() ?? os.cpus().length
const pinned = options.pin && !target && cpuCount >= 2
const serverCpus = pinned ? '0' : undefined
const k6Cpus = pinned ? `1-${cpuCount - 1}` : undefined

const children = { server: null, k6: null }
let interrupted = false
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, () => {
    if (interrupted) process.exit(130)
    interrupted = true
    console.error(`\n${signal}: stopping k6 and the server …`)
    children.k6?.kill('SIGINT')
  })
}

const exitCode = await main()
process.exit(exitCode)

async function main () {
  const tempDir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-loadtest-'))
  const profileDir = options.profile && !target ? path.join(outDir, 'profile') : undefined
  const snapshotHz = options.snapshotHz ? { SNAPSHOT_HZ: String(options.snapshotHz) } : {}
  let server = null
  try {
    if (!target) {
      console.log(`starting the server (fresh SQLite ledger in ${tempDir}${profileDir ? ', --cpu-prof' : ''}${serverCpus ? `, CPU ${serverCpus}` : ''}) …`)
      server = await startServer({ dataDir: tempDir, logFile: path.join(outDir, 'server.log'), env: { ...snapshotHz, ...options.serverEnv }, profileDir, cpus: serverCpus })
      children.server = server
    }
    const url = target ?? server.url
    const sampler = new MetricsSampler({ url, intervalMs: options.sampleIntervalS * 1000, pids: { server: server?.pid } })
    const samplerStartedNs = process.hrtime.bigint()
    sampler.start()
    await sleep(BASELINE_MS)
    const baselineIndex = sampler.samples.length - 1

    const k6Result = await runK6(url, sampler)
    await sleep(AFTER_MS)
    await sampler.stop()
    const serverExit = server ? await server.stop() : null
    if (serverExit) console.log(`server stopped (exit ${serverExit.code ?? serverExit.signal})`)

    const analysis = analyzeServerSamples(sampler.samples, { expectedClients: options.vus, baselineIndex })
    const profile = profileDir ? profileOf(profileDir, analysis.window, samplerStartedNs) : null
    const k6Summary = readJson(path.join(outDir, 'k6-summary.json'))
    fs.writeFileSync(path.join(outDir, 'samples.json'), JSON.stringify({ options, url, samples: sampler.samples }, null, 1))
    const rooms = k6Summary?.setup_data?.rooms?.length ?? options.rooms
    const title = `${options.scenario}: ${options.vus} players, ${rooms} rooms, one drop per ${options.dropIntervalS} s`
    fs.writeFileSync(path.join(outDir, 'chart.svg'), renderChart({ title, points: analysis.series, window: analysis.window, panels: chartPanels() }))
    const files = fs.readdirSync(outDir).concat(['report.md']).filter((f, i, all) => all.indexOf(f) === i).sort()
    fs.writeFileSync(path.join(outDir, 'report.md'), renderReport({
      title,
      command,
      machine: machine(),
      settings: settings(url, k6Summary),
      server: analysis,
      k6: k6Summary,
      k6ExitCode: k6Result.code,
      serverExit,
      profile,
      files
    }))

    printVerdict(analysis, k6Summary)
    console.log(`report: ${path.relative(process.cwd(), path.join(outDir, 'report.md'))}`)
    if (interrupted) return 130
    if (k6Result.code !== 0) return k6Result.code ?? 1
    if (!k6Summary) return 1
    if (serverExit && serverExit.code !== 0) return 1
    return 0
  } catch (error) {
    console.error(`load test failed: ${error.message}`)
    return 1
  } finally {
    if (server && !server.exited) await server.stop().catch(() => {})
    fs.rmSync(tempDir, { recursive: true, force: true })
  }
}

/** Runs the scenario; k6's output goes to the console (trimmed) and to k6-output.txt (whole). */
function runK6 (url, sampler) {
  const env = {
    BASE_URL: url,
    VUS: options.vus,
    ROOMS: options.rooms,
    DROP_INTERVAL: `${options.dropIntervalS}s`,
    DELIVERY: options.delivery,
    BREAKDOWN: '1',
    ...(options.durationS !== undefined && { DURATION: `${options.durationS}s` }),
    ...(options.rampS !== undefined && { RAMP: `${options.rampS}s` }),
    ...(options.leaveS !== undefined && { LEAVE: `${options.leaveS}s` }),
    ...(options.drainS !== undefined && { DRAIN: `${options.drainS}s` }),
    ...(options.bet !== undefined && { BET: options.bet }),
    ...options.k6Env
  }
  const args = ['run', '--no-usage-report', '-q', '--summary-export', path.join(outDir, 'k6-summary.json'),
    ...Object.entries(env).flatMap(([key, value]) => ['-e', `${key}=${value}`]),
    path.join(HERE, `${options.scenario}.js`)]
  const [cmd, cmdArgs] = k6Cpus ? ['taskset', ['-c', k6Cpus, k6, ...args]] : [k6, args]
  console.log(`k6 ${options.scenario}: ${options.vus} players, ${options.rooms} rooms, drop every ${options.dropIntervalS} s${k6Cpus ? `, CPUs ${k6Cpus}` : ''} …`)
  // GOGC=400: k6 spends a fifth of its CPU in Go's GC at the default 100; memory is cheaper here.
  const child = spawn(cmd, cmdArgs, { env: { GOGC: '400', ...process.env, K6_NO_USAGE_REPORT: 'true' }, stdio: ['ignore', 'pipe', 'pipe'] })
  children.k6 = child
  sampler.pids.k6 = child.pid
  const log = fs.createWriteStream(path.join(outDir, 'k6-output.txt'))
  for (const [stream, out] of [[child.stdout, process.stdout], [child.stderr, process.stderr]]) {
    readline.createInterface({ input: stream }).on('line', (line) => {
      log.write(line + '\n')
      // The per-code and per-kind breakdown only feeds the report.
      if (/'count>=0'/.test(line) || /^\s+\w+\{(code|kind):[^}]*\}\s*$/.test(line) || /^\s+\{ (code|kind):/.test(line)) return
      out.write(line + '\n')
    })
  }
  return new Promise((resolve) => {
    child.once('error', (error) => { console.error(`k6: ${error.message}`); resolve({ code: 1 }) })
    child.once('exit', (code, signal) => {
      children.k6 = null
      log.end()
      resolve({ code: code ?? (signal ? 1 : 0), signal })
    })
  })
}

function chartPanels () {
  return [
    { title: 'Connected players', unit: 'count', lines: [{ key: 'clients', label: 'players' }, { key: 'balls', label: 'balls in flight' }] },
    { title: 'Tick and event loop', unit: 'ms, p99 per interval', lines: [{ key: 'tickP99Ms', label: 'tick duration' }, { key: 'tickLagP99Ms', label: 'tick lag' }, { key: 'eventLoopP99Ms', label: 'event-loop delay' }], goal: { value: TICK_P99_GOAL_S * 1000, label: '8 ms goal' } },
    { title: 'CPU', unit: '% of one core', lines: [{ key: 'serverCpu', label: 'server' }, { key: 'k6Cpu', label: 'k6' }, { key: 'machineCpu', label: 'whole machine' }] },
    { title: 'Server memory', unit: 'MB', lines: [{ key: 'rssMb', label: 'RSS' }, { key: 'heapMb', label: 'JS heap used' }] },
    { title: 'Server bytes out per player', unit: 'bytes/s', lines: [{ key: 'bytesOutPerClient', label: 'payload' }] }
  ]
}

/** The profile's summary over the steady window (the whole profile if the clocks do not line up). */
function profileOf (dir, window, samplerStartedNs) {
  const file = fs.existsSync(dir) ? fs.readdirSync(dir).find((f) => f.endsWith('.cpuprofile')) : null
  if (!file) {
    console.warn(`no .cpuprofile in ${dir}`)
    return null
  }
  const profile = readJson(path.join(dir, file))
  // V8 profile times and process.hrtime are both CLOCK_MONOTONIC, in µs and ns.
  const samplerStartUs = Number(samplerStartedNs / 1000n)
  let range = {}
  if (window) {
    const from = samplerStartUs + window.from * 1e6 - profile.startTime
    const to = samplerStartUs + window.to * 1e6 - profile.startTime
    if (from >= 0 && to <= profile.endTime - profile.startTime + 1e6) range = { from, to }
  }
  return { file: path.relative(outDir, path.join(dir, file)), summary: summarizeCpuProfile(profile, range) }
}

function printVerdict (analysis, k6Summary) {
  const m = k6Summary?.metrics ?? {}
  const t = analysis.tick
  console.log([
    '',
    `players ${fmt(analysis.clients?.peak)} | tick p99 ${t?.p99 != null ? `${fmt(t.p99 * 1000, 2)} ms` : '–'} (≤ 8 ms: ${t?.within8ms != null ? `${fmt(t.within8ms * 100, 1)}%` : '–'})` +
      ` | CPU (100% = 1 core): server ${percent(analysis.cpu?.server)}, k6 ${percent(analysis.cpu?.k6)}, others ${percent(analysis.cpu?.others)}`,
    `errors ${fmt(m.plinko_errors?.count)} | unsettled ${fmt(m.unsettled_drops?.count)} | drop→settled p50 ${fmt(m.drop_settled_ms?.med, 0)} ms p99 ${fmt(m.drop_settled_ms?.['p(99)'], 0)} ms` +
      ` (minus flight: p99 ${fmt(m.drop_settle_overhead_ms?.['p(99)'], 1)} ms) | ${fmt(analysis.traffic?.bytesPerClientPerSecond, 0)} B/s per player` +
      ` | RSS per player ${analysis.memory?.rssPerClient != null ? `${fmt(analysis.memory.rssPerClient / 1024, 1)} KB` : '–'}`
  ].join('\n'))
}

function percent (fraction) {
  return fraction === null || fraction === undefined ? '–' : `${fmt(fraction * 100, 0)}%`
}

function settings (url, k6Summary) {
  const rooms = k6Summary?.setup_data?.rooms
  return {
    scenario: options.scenario,
    'players (VUs)': options.vus,
    rooms: rooms && rooms.length !== options.rooms ? `${rooms.length} (asked for ${options.rooms}; the server offers ${rooms.length})` : options.rooms,
    'drop interval': `${options.dropIntervalS} s`,
    delivery: options.delivery === 'seeds' ? 'seeds (drop-events frames, no positions)' : 'snapshots (positions)',
    'steady duration': options.durationS !== undefined ? `${options.durationS} s` : 'scenario default',
    ramp: options.rampS !== undefined ? `${options.rampS} s` : 'scenario default',
    server: target ? `${url} (TARGET_URL, not started by the run)` : `${url}, SQLite (WAL, synchronous=FULL) in a temp folder`,
    'server environment': Object.entries({ ...(options.snapshotHz && { SNAPSHOT_HZ: options.snapshotHz }), ...options.serverEnv }).map(([k, v]) => `${k}=${v}`).join(' ') || '(defaults; SNAPSHOT_HZ=20)',
    'CPU pinning': pinned ? `server CPU ${serverCpus}, k6 CPUs ${k6Cpus}` : 'none (server and k6 share every core)'
  }
}

function machine () {
  return {
    CPU: `${os.cpus()[0]?.model ?? 'unknown'} × ${cpuCount}`,
    cores: cpuCount,
    memory: `${fmt(os.totalmem() / 2 ** 30, 1)} GiB`,
    OS: `${os.type()} ${os.release()}`,
    Node: process.version,
    k6: k6VersionOf(k6) ?? 'unknown',
    date: new Date().toISOString()
  }
}

function readJson (file) {
  try {
    return JSON.parse(fs.readFileSync(file, 'utf8'))
  } catch {
    return null
  }
}

function sleep (ms) {
  return new Promise((resolve) => setTimeout(resolve, ms))
}
