#!/usr/bin/env node
/**
 * `npm run loadtest:cluster-capacity -- [--steps 1000,1500,…] [--rooms 100] [--duration 20s] [--ramp 15s]`
 *
 * Players held by one server process and by `npm run cluster -- --workers 2`
 * (two processes behind the cluster's proxy, rooms leased through Redis),
 * in one run, with the same lean load generator (loadtest/lean/) and the
 * same criteria as `npm run loadtest:capacity` (tick p99 < 8 ms and tick
 * lag p99 < 16.7 ms on every process, 0 errors, every drop settled,
 * drop → dropped p99 < 250 ms). Both share a throwaway PostgreSQL ledger
 * (the cluster needs one; the single process uses it too, so only the
 * process count differs), a fresh database per step. The generator enters
 * through one URL; a player whose room runs on the other process follows
 * E_WRONG_NODE there. Nothing is pinned: the processes, the proxy, Redis,
 * PostgreSQL and the generator share this machine's CPUs, and the table
 * says how much of them each used.
 *
 * Steps per mode go up until the first that fails. Prints the table and
 * the ratio of players held and writes them to loadtest/RESULTS.md between
 * the `cluster-capacity:begin` / `:end` markers (--no-results: print
 * only); exit code 0 whatever the figures, 2 for a bad command line.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { parseCommandLine } from '../../cli/command-line.js'
import { optionsOrExit } from '../../cli/usage-error.js'
import { parseDuration, positiveInteger } from '../driver/cli-args.js'
import { startServer } from '../driver/server-process.js'
import { MetricsSampler, readProcStat } from '../driver/metrics-sampler.js'
import { analyzeServerSamples } from '../driver/run-analysis.js'
import { runLeanLoad, formatLeanSummary } from './lean-generator.js'
import { CRITERIA, STEP_OPTIONS, f, pct, serverErrorCount, writeBetweenMarkers } from './capacity.js'
import { startPostgres } from '../../tools/postgres-process.js'
import { startRedis } from '../../tools/redis-process.js'
import { startClusterProcess } from '../../tools/cluster-process.js'

const RESULTS = fileURLToPath(new URL('../RESULTS.md', import.meta.url))
export const CLUSTER_SECTION = Object.freeze({
  begin: '<!-- cluster-capacity:begin (written by npm run loadtest:cluster-capacity) -->',
  end: '<!-- cluster-capacity:end -->',
  heading: 'Two processes (npm run loadtest:cluster-capacity)'
})
const OPERATOR_TOKEN = 'operator-token-for-cluster-capacity-0123'

export const USAGE = `usage: npm run loadtest:cluster-capacity -- [options]

  --steps N,N,…    player counts to try per mode, in order (default 500,1000,1500,2000,2500,3000)
  --rooms N        rooms (default 100)
  --duration TIME  steady phase per step (default 20s)
  --ramp TIME      players connect spread over this (default 15s)
  --no-results     print only; do not write loadtest/RESULTS.md
  -h, --help`

/** @param {string[]} argv */
export function parseClusterCapacityArgs (argv) {
  const values = parseCommandLine(argv, STEP_OPTIONS, { repeated: 'last' })
  if (values.help) return { help: true }
  return {
    help: false,
    steps: (values.steps ?? '500,1000,1500,2000,2500,3000').split(',').map((raw) => positiveInteger(raw.trim(), 'steps')),
    rooms: values.rooms === undefined ? 100 : positiveInteger(values.rooms, 'rooms'),
    durationS: parseDuration(values.duration ?? '20s', 'duration'),
    rampS: parseDuration(values.ramp ?? '15s', 'ramp'),
    writeResults: !values['no-results']
  }
}

/** The pids of a process and its children (the cluster's workers), from /proc. @param {number} pid */
function processTree (pid) {
  const pids = [pid]
  for (let i = 0; i < pids.length; i++) {
    try {
      for (const task of fs.readdirSync(`/proc/${pids[i]}/task`)) {
        const children = fs.readFileSync(`/proc/${pids[i]}/task/${task}/children`, 'utf8').trim()
        if (children) pids.push(...children.split(' ').map(Number))
      }
    } catch {}
  }
  return pids
}

/** One server process on PostgreSQL. */
async function startOne (databaseUrl, dir) {
  const server = await startServer({ dataDir: dir, logFile: path.join(dir, 'server.log'), env: { DATABASE_URL: databaseUrl } })
  return { url: server.url, processes: [server.url], proxyPid: null, pids: () => [server.pid], stop: () => server.stop() }
}

/** `npm run cluster -- --workers 2` (scripts/cluster.js) on PostgreSQL and Redis, its output in `dir`/cluster.log. */
async function startTwo (databaseUrl, redisUrl, dir) {
  const log = fs.openSync(path.join(dir, 'cluster.log'), 'a')
  let cluster
  try {
    cluster = await startClusterProcess({ workers: 2, env: { DATABASE_URL: databaseUrl, REDIS_URL: redisUrl, OPERATOR_TOKEN, CLIENT_DIR: '/nonexistent/plinko-client' }, stdio: ['ignore', log, log] })
  } finally {
    fs.closeSync(log)
  }
  return {
    url: cluster.url,
    processes: cluster.processes,
    // scripts/cluster.js itself is the proxy; its children are the workers.
    proxyPid: cluster.child.pid,
    pids: () => processTree(cluster.child.pid),
    stop: () => cluster.stop(60_000)
  }
}

/**
 * One step: `players` under the reference load on a fresh target; the
 * criteria over the generator's steady window, tick figures the worst of
 * the processes'.
 */
async function measureStep (start, { players, rooms, durationS, rampS }) {
  const target = await start()
  const samplers = target.processes.map((url) => new MetricsSampler({ url, intervalMs: 1000 }))
  let from = null
  let to = null
  const read = () => {
    const pids = target.pids()
    return { at: performance.now(), pids, cpuS: new Map(pids.map((pid) => [pid, readProcStat(pid)?.cpuS ?? null])), generator: process.cpuUsage() }
  }
  try {
    for (const sampler of samplers) sampler.start()
    await new Promise((resolve) => setTimeout(resolve, 1500))
    const summary = await runLeanLoad({
      baseUrl: target.url, players, rooms, durationS, rampS, dropIntervalMs: 2000, drainS: 15,
      window: { start: () => { from = read() }, end: () => { to = read() } }
    })
    for (const sampler of samplers) await sampler.stop()
    // expectedClients 0: each process's own plateau (the players split between them by room).
    const analyses = samplers.map((sampler) => analyzeServerSamples(sampler.samples, { expectedClients: 0 }))
    const seconds = (to.at - from.at) / 1000
    // CPU of the processes there over the whole window (the proxy and the workers; a restarted worker would not be).
    const serverCpuS = from.pids.reduce((total, pid) => {
      const [a, b] = [from.cpuS.get(pid), to.cpuS.get(pid)]
      return a === null || b === null || b === undefined ? total : total + b - a
    }, 0)
    const generatorCpuS = (to.generator.user - from.generator.user + to.generator.system - from.generator.system) / 1e6
    const proxyCpuS = target.proxyPid === null ? null : (to.cpuS.get(target.proxyPid) ?? 0) - (from.cpuS.get(target.proxyPid) ?? 0)
    const step = clusterStepFigures({ players, analyses, summary, serverShare: serverCpuS / seconds, proxyShare: proxyCpuS === null ? null : proxyCpuS / seconds, generatorShare: generatorCpuS / seconds })
    return step
  } finally {
    for (const sampler of samplers) if (sampler.running) await sampler.stop()
    await target.stop()
  }
}

/**
 * One step's figures and verdict: the generator's, and the worst of the
 * processes' tick figures (a step holds only if every process does).
 * serverShare: cores used by the server processes and the proxy together; proxyShare: by the proxy (null: none).
 * @param {{ players: number, analyses: ReturnType<typeof analyzeServerSamples>[], summary: Awaited<ReturnType<typeof runLeanLoad>>, serverShare: number, proxyShare?: number | null, generatorShare: number }} measured
 */
export function clusterStepFigures ({ players, analyses, summary, serverShare, proxyShare = null, generatorShare }) {
  const worst = (read) => {
    const values = analyses.map(read)
    return values.some((value) => value === null || value === undefined) ? null : Math.max(...values) * 1000
  }
  const step = {
    players,
    processes: analyses.length,
    serverShare,
    proxyShare,
    generatorShare,
    tickP99Ms: worst((a) => a.tick?.p99),
    lagP99Ms: worst((a) => a.tickLag?.p99),
    ackP50Ms: summary.steady.ackMs.p50,
    ackP99Ms: summary.steady.ackMs.p99,
    settledP99Ms: summary.steady.settledMs.p99,
    dropsSent: summary.dropsSent,
    dropsSettled: summary.dropsSettled,
    unsettled: summary.unsettled,
    redirects: summary.redirects,
    errors: summary.errorCount,
    serverErrors: analyses.reduce((total, a) => total + serverErrorCount(a), 0),
    summary
  }
  step.failed = CRITERIA.filter((criterion) => !criterion.holds(step)).map((criterion) => criterion.name)
  step.holds = step.failed.length === 0
  return step
}

/** The table of both modes' steps and the verdict. */
export function clusterCapacityMarkdown (modes, { rooms, durationS, cpus, date = new Date() }) {
  const held = (steps) => Math.max(0, ...steps.filter((step) => step.holds).map((step) => step.players))
  const [one, two] = modes.map((mode) => held(mode.steps))
  const header = '| processes | players | server CPU (processes + proxy) | of which the proxy | generator CPU | tick p99 (worst) | lag p99 (worst) | drop → dropped p50 / p99 | drop → settled p99 | redirects | errors, unsettled | verdict |'
  const rows = modes.flatMap((mode) => mode.steps.map((step) => `| ${mode.label} | ${step.players.toLocaleString('en-US')} | ${pct(step.serverShare)} | ${step.proxyShare === null ? '–' : pct(step.proxyShare)} | ${pct(step.generatorShare)} | ${f(step.tickP99Ms, 2)} ms | ${f(step.lagP99Ms, 2)} ms | ${f(step.ackP50Ms, 0)} / ${f(step.ackP99Ms, 0)} ms | ${f(step.settledP99Ms, 0)} ms | ${step.redirects} | ${step.errors + step.serverErrors}, ${step.unsettled} | ${step.holds ? 'holds' : `fails: ${step.failed.join(', ')}`} |`))
  return [
    `Last run: ${date.toISOString().slice(0, 16).replace('T', ' ')} UTC, ${cpus} CPUs shared by everything (not pinned), PostgreSQL ledger, ${rooms} rooms, one drop per player every 2 s, ${durationS} s steady phase per step.`,
    '',
    `**Players held: one process ${one.toLocaleString('en-US')}, two processes (npm run cluster -- --workers 2) ${two.toLocaleString('en-US')}: ${one > 0 ? `${(two / one).toFixed(2)}×` : '–'}** (criteria: ${CRITERIA.map((c) => c.name).join(', ')}).`,
    '',
    header,
    `|${header.split('|').slice(1, -1).map(() => ' ---').join(' |')} |`,
    ...rows
  ].join('\n')
}

async function main () {
  const options = optionsOrExit(parseClusterCapacityArgs, process.argv.slice(2), USAGE)
  const postgres = await startPostgres()
  const redis = await startRedis()
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-cluster-capacity-'))
  const modes = [
    { label: '1', start: async () => startOne(await postgres.createDatabase(), dir), steps: [] },
    { label: '2', start: async () => startTwo(await postgres.createDatabase(), redis.url, dir), steps: [] }
  ]
  console.log(`cluster capacity: steps ${options.steps.join(', ')}; ${options.rooms} rooms; one process, then two (logs in ${dir})`)
  try {
    for (const mode of modes) {
      for (const players of options.steps) {
        const step = await measureStep(mode.start, { players, ...options })
        mode.steps.push(step)
        console.log(`${mode.label} process${mode.label === '1' ? '' : 'es'}, ${players} players: ${step.holds ? 'holds' : `fails (${step.failed.join(', ')})`}; server ${pct(step.serverShare)}${step.proxyShare === null ? '' : ` (proxy ${pct(step.proxyShare)})`}, generator ${pct(step.generatorShare)}; tick p99 ${f(step.tickP99Ms, 2)} ms, lag p99 ${f(step.lagP99Ms, 2)} ms; ack p99 ${f(step.ackP99Ms, 0)} ms; ${step.redirects} redirects`)
        if (!step.summary.passed) console.log(formatLeanSummary(step.summary))
        if (!step.holds) break
      }
    }
  } finally {
    await redis.stop()
    await postgres.stop()
  }
  const markdown = clusterCapacityMarkdown(modes, { ...options, cpus: os.availableParallelism() })
  console.log(`\n${markdown}`)
  if (options.writeResults) {
    writeBetweenMarkers(RESULTS, markdown, CLUSTER_SECTION)
    console.log(`\nwritten to ${path.relative(process.cwd(), RESULTS)}`)
  }
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) await main()
