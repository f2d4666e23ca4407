#!/usr/bin/env node
/**
 * `npm run loadtest:capacity -- [options]`: how many players one server
 * process holds on one core, in each delivery mode (--delivery, default
 * both, side by side). For each player count in --steps: the bare
 * WebSocket floor with that many clients (measure-server.js), then for each
 * mode a fresh server (server/server.js, SQLite ledger) pinned to CPU 0
 * under the lean load generator on CPU 1 with the reference load (one drop
 * per player every 2 s, 20 Hz snapshots or 4 Hz drop events, --rooms
 * rooms), /metrics read every second. --ledger postgres puts the ledger
 * in a throwaway PostgreSQL (its own flush on every commit) on CPU 1 beside
 * the generator, a fresh database per step, as a server beside its database
 * host runs: the server's figures then leave out the database's own work
 * (the SQLite writer thread is the server's). --steer-loopback runs the
 * loopback's receive processing on CPU 1 (driver/loopback-steering.js; Linux,
 * root): the generator's TCP receive of the server's frames then leaves the
 * server's core, as the players' machines would pay it. A run holds when
 * every criterion does (CRITERIA below). --repeat N measures each step N times, the modes
 * taking turns run by run (this VM's speed drifts by a third within an hour,
 * so one run of a step at the edge is a coin's toss): a step holds when all
 * its runs do, and the table says how many did. A mode stops stepping after
 * a step none of whose runs held (--all: runs every step).
 *
 * Prints one line per step and writes the table to loadtest/RESULTS.md
 * between the `capacity:begin` / `capacity:end` markers (--no-results:
 * print only). Exit code 0 whatever the figures, 2 for a bad command line.
 */
import fs from 'node:fs'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { parseCommandLine } from '../../cli/command-line.js'
import { optionsOrExit } from '../../cli/usage-error.js'
import { parseDuration, positiveInteger, deliveryMode, UsageError } from '../driver/cli-args.js'
import { DELIVERY_MODES } from '../../protocol/client-messages.js'
import { formatLeanSummary } from './lean-generator.js'
import { canPin, pinSelf, measureFloor, measureOurs } from './measure-server.js'
import { startPostgres } from '../../tools/postgres-process.js'
import { steerLoopbackReceiveUntilExit } from '../driver/loopback-steering.js'

const RESULTS = fileURLToPath(new URL('../RESULTS.md', import.meta.url))
export const BEGIN_MARKER = '<!-- capacity:begin (written by npm run loadtest:capacity) -->'
export const END_MARKER = '<!-- capacity:end -->'

/**
 * The generator's worker threads by default. Every latency the generator
 * measures includes how late its event loop is when it reads a frame: at
 * 6,000 players on its one CPU, one thread was late by 30–36 ms at p99 and
 * two by 16–23, with the same share of that CPU (loadtest/RESULTS.md).
 */
export const GENERATOR_WORKERS = 2

/** Every criterion a step must meet; `value` reads it from a step's figures. */
export const CRITERIA = [
  { name: 'tick p99 < 8 ms', holds: (step) => step.tickP99Ms !== null && step.tickP99Ms < 8 },
  { name: 'tick lag p99 < 16.7 ms', holds: (step) => step.lagP99Ms !== null && step.lagP99Ms < 16.7 },
  { name: '0 errors', holds: (step) => step.errors === 0 && step.serverErrors === 0 },
  { name: 'every drop settled', holds: (step) => step.unsettled === 0 && step.dropsSettled === step.dropsSent && step.dropsSent > 0 },
  { name: 'drop → dropped p99 < 250 ms', holds: (step) => step.ackP99Ms !== null && step.ackP99Ms < 250 },
  // Measured in seeds mode (the lean player decodes the drop-events frames); snapshots mode's room frames are not parsed.
  { name: "another player's drop reaches its room p99 ≤ 300 ms (seeds)", holds: (step) => step.delivery !== 'seeds' || (step.sightingP99Ms !== null && step.sightingP99Ms <= 300) }
]

export const USAGE = `usage: npm run loadtest:capacity -- [options]

  --steps N,N,…        player counts to try, in order (default 1000,1500,2000,2500,3000,3500,4000)
  --rooms N            rooms (default 100)
  --duration TIME      steady phase per step (default 30s)
  --ramp TIME          players connect spread over this (default 20s)
  --floor-seconds TIME the floor's window per step (default 10s; 0 = no floor)
  --workers N          generator worker threads (default 2: one thread's event loop, late by 30-36 ms at p99
                       with 6,000 players, adds that to every latency it measures)
  --delivery LIST      modes to measure, side by side: snapshots,seeds (default both)
  --ledger STORE       sqlite (default: a file beside the server, its writer thread on the server's core)
                       or postgres (a throwaway PostgreSQL on the generator's core)
  --steer-loopback     the loopback's receive processing (RPS) on the generator's CPU 1, both directions:
                       the generator's TCP receive leaves the server's core, as on a real network
                       (Linux and root; restored after the run); the table goes in a section of its own
  --repeat N           measure each step N times, the modes interleaved run by run (default 1);
                       a step holds when every one of its runs does, and the table says how many did
  --all                run every step, not only up to the first that fails
  --no-results         print only; do not write loadtest/RESULTS.md
  -h, --help`

/** The options every stepping run takes (this one and cluster-capacity.js). */
export const STEP_OPTIONS = Object.freeze({
  help: { type: 'boolean', short: 'h' },
  steps: { type: 'string' },
  rooms: { type: 'string' },
  duration: { type: 'string' },
  ramp: { type: 'string' },
  'no-results': { type: 'boolean', default: false }
})

const OPTIONS = {
  ...STEP_OPTIONS,
  'floor-seconds': { type: 'string' },
  workers: { type: 'string' },
  delivery: { type: 'string' },
  ledger: { type: 'string' },
  repeat: { type: 'string' },
  'steer-loopback': { type: 'boolean', default: false },
  all: { type: 'boolean', default: false }
}

/** The ledgers a capacity run can put behind the server. */
export const CAPACITY_LEDGERS = Object.freeze(['sqlite', 'postgres'])

/** @param {string[]} argv */
export function parseCapacityArgs (argv) {
  const values = parseCommandLine(argv, OPTIONS, { repeated: 'last' })
  if (values.help) return { help: true }
  const steps = (values.steps ?? '1000,1500,2000,2500,3000,3500,4000').split(',').map((raw) => positiveInteger(raw.trim(), 'steps'))
  return {
    help: false,
    steps,
    rooms: values.rooms === undefined ? 100 : positiveInteger(values.rooms, 'rooms'),
    durationS: parseDuration(values.duration ?? '30s', 'duration'),
    rampS: parseDuration(values.ramp ?? '20s', 'ramp'),
    floorSeconds: parseDuration(values['floor-seconds'] ?? '10s', 'floor-seconds'),
    workers: values.workers === undefined ? GENERATOR_WORKERS : positiveInteger(values.workers, 'workers'),
    deliveries: [...new Set((values.delivery ?? DELIVERY_MODES.join(',')).split(',').map((raw) => deliveryMode(raw.trim(), 'delivery')))],
    ledger: capacityLedger(values.ledger ?? 'sqlite'),
    repeat: values.repeat === undefined ? 1 : positiveInteger(values.repeat, 'repeat'),
    steerLoopback: values['steer-loopback'],
    all: values.all,
    writeResults: !values['no-results']
  }
}

/** @param {string} raw */
function capacityLedger (raw) {
  if (!CAPACITY_LEDGERS.includes(raw)) throw new UsageError(`--ledger must be one of ${CAPACITY_LEDGERS.join(', ')}, got ${raw}`)
  return raw
}

/**
 * One step's figures from measureOurs() (and the floor's, when measured).
 * @param {Awaited<ReturnType<typeof measureOurs>>} ours
 * @param {Awaited<ReturnType<typeof measureFloor>> | null} floor
 */
export function stepFigures (ours, floor) {
  const s = ours.summary
  const a = ours.analysis
  const ms = (seconds) => seconds === null || seconds === undefined ? null : seconds * 1000
  const steadyDrops = s.steady.ackMs.count
  const step = {
    players: ours.players,
    delivery: ours.delivery ?? 'snapshots',
    serverShare: ours.serverShare,
    /** Server CPU per player-second (µs): its share of a core spread over the players. */
    serverUsPerPlayerSecond: ours.serverShare !== undefined && ours.players > 0 ? ours.serverShare * 1e6 / ours.players : null,
    /** Server CPU per drop (µs), everything included (frames too): CPU of the steady window over the drops sent in it. */
    serverUsPerDrop: ours.serverCpuS !== undefined && steadyDrops > 0 ? ours.serverCpuS * 1e6 / steadyDrops : null,
    sightingP50Ms: s.steady.sightingMs?.p50 ?? null,
    sightingP99Ms: s.steady.sightingMs?.p99 ?? null,
    /** Room ticks from a ball's release to the frame that carried it, p99: the room's part of the sighting (its batching and holds). */
    sightingTicksP99: s.steady.sightingTicks?.p99 ?? null,
    serverUsPerFrame: ours.serverUsPerFrame,
    floorUsPerFrame: floor?.serverUsPerFrame ?? null,
    ratio: floor ? ours.serverUsPerFrame / floor.serverUsPerFrame : null,
    tickP99Ms: ms(a?.tick?.p99),
    lagP99Ms: ms(a?.tickLag?.p99),
    /** Group commits over 50 ms in the steady window, which every drop in them waits for: the writer thread's wait for the core, or the disk. */
    slowCommits: a?.commit?.over50ms ?? null,
    /**
     * Share of the window the SQLite writer thread was runnable but waited for
     * the core (it runs at nice 10, below the event loop): with many slow
     * commits, a high share says the commits waited for the CPU, not the disk.
     */
    writerWaitShare: ours.writerWaitShare ?? null,
    // Drops sent in the steady window: the ramp's connects (one fsync'd session each) are not the load being measured.
    ackP50Ms: s.steady.ackMs.p50,
    ackP99Ms: s.steady.ackMs.p99,
    settledP50Ms: s.steady.settledMs.p50,
    settledP99Ms: s.steady.settledMs.p99,
    ackP99AllMs: s.ackMs.p99,
    dropsSent: s.dropsSent,
    dropsSettled: s.dropsSettled,
    unsettled: s.unsettled,
    errors: s.errorCount,
    serverErrors: serverErrorCount(a),
    framesPerSecondPerPlayer: s.window.framesPerSecondPerPlayer,
    bytesPerSecondPerPlayer: s.window.bytesPerSecondPerPlayer,
    rssPerClient: a?.memory?.rssPerClient ?? null,
    generatorShare: s.cpu.shareOfCore,
    generatorUsPerFrame: s.cpu.usPerFrame,
    generatorLateP99Ms: s.cpu.loopDelay?.p99Ms ?? null,
    othersShare: ours.othersShare
  }
  step.failed = CRITERIA.filter((criterion) => !criterion.holds(step)).map((criterion) => criterion.name)
  step.holds = step.failed.length === 0
  return step
}

/** A figure for the tables: thousands grouped, `digits` decimals, – when there is none. @param {number | null | undefined} value @param {number} [digits] */
export const f = (value, digits = 1) => value === null || value === undefined || Number.isNaN(value) ? '–' : Number(value).toLocaleString('en-US', { minimumFractionDigits: digits, maximumFractionDigits: digits })
/** A share of a core as a whole percentage. @param {number | null | undefined} share */
export const pct = (share) => share === null || share === undefined ? '–' : `${f(share * 100, 0)}%`

/**
 * The error replies a server process counted (plinko_errors_total, from
 * run-analysis.js), but for E_WRONG_NODE: a clustered join sent to the
 * room's process, which the generator followed and counts as a redirect.
 * @param {{ serverErrors?: Record<string, number> } | null | undefined} analysis
 */
export function serverErrorCount (analysis) {
  let total = 0
  for (const [code, count] of Object.entries(analysis?.serverErrors ?? {})) if (code !== 'E_WRONG_NODE') total += count
  return total
}

/**
 * Each step's runs, by mode in the order measured, and how many of them held.
 * A step holds when every one of its runs did (`--repeat 1`: its one run).
 * @param {ReturnType<typeof stepFigures>[]} steps
 * @returns {{ delivery: string, players: number, runs: number, held: number }[]}
 */
export function stepTallies (steps) {
  const tallies = new Map()
  for (const step of steps) {
    const delivery = step.delivery ?? 'snapshots'
    const key = `${delivery} ${step.players}`
    const tally = tallies.get(key) ?? { delivery, players: step.players, runs: 0, held: 0 }
    tally.runs++
    if (step.holds) tally.held++
    tallies.set(key, tally)
  }
  return [...tallies.values()]
}

/** The markdown table of the steps, and the verdict. @param {(ReturnType<typeof stepFigures> & { run?: number })[]} steps @param {object} options */
export function capacityMarkdown (steps, { rooms, durationS, pinned, ledger = 'sqlite', steered = false, workers = GENERATOR_WORKERS, date = new Date() }) {
  const modes = [...new Set(steps.map((step) => step.delivery ?? 'snapshots'))]
  const tallies = stepTallies(steps)
  const repeated = tallies.some((tally) => tally.runs > 1)
  const bestOf = (mode) => {
    const held = tallies.filter((tally) => tally.delivery === mode && tally.held === tally.runs).map((tally) => tally.players)
    return held.length ? Math.max(...held).toLocaleString('en-US') : 'none of the steps'
  }
  const runsHeld = modes.map((mode) => `${mode} ${tallies.filter((tally) => tally.delivery === mode).map((tally) => `${tally.players.toLocaleString('en-US')} ${tally.held} of ${tally.runs}`).join(', ')}`).join('; ')
  const playersCell = (step) => repeated && step.run !== undefined ? `${step.players.toLocaleString('en-US')} (run ${step.run})` : step.players.toLocaleString('en-US')
  const header = '| players | delivery | server CPU | server µs/frame | floor µs/frame | ratio | server µs per player-second | server µs per drop | tick p99 | lag p99 | commits > 50 ms, writer waiting for the CPU | drop → dropped p50 / p99 | drop → settled p50 / p99 | drop → seen by the room p50 / p99 | errors, unsettled | frames/s, KB/s per player | RSS per player | generator CPU, µs/frame, loop late p99 | other processes | verdict |'
  const rows = steps.map((step) => `| ${playersCell(step)} | ${step.delivery ?? 'snapshots'} | ${pct(step.serverShare)} | ${f(step.serverUsPerFrame)} | ${f(step.floorUsPerFrame)} | ${step.ratio === null ? '–' : `${f(step.ratio, 2)}×`} | ${f(step.serverUsPerPlayerSecond, 0)} | ${f(step.serverUsPerDrop, 0)} | ${f(step.tickP99Ms, 2)} ms | ${f(step.lagP99Ms, 2)} ms | ${f(step.slowCommits, 0)}, ${pct(step.writerWaitShare)} | ${f(step.ackP50Ms, 0)} / ${f(step.ackP99Ms, 0)} ms | ${f(step.settledP50Ms, 0)} / ${f(step.settledP99Ms, 0)} ms | ${step.delivery === 'seeds' ? `${f(step.sightingP50Ms, 0)} / ${f(step.sightingP99Ms, 0)} ms` : '–'} | ${step.errors + step.serverErrors}, ${step.unsettled} | ${f(step.framesPerSecondPerPlayer)}, ${f(step.bytesPerSecondPerPlayer / 1000, 2)} | ${step.rssPerClient === null ? '–' : `${f(step.rssPerClient / 1000, 0)} KB`} | ${pct(step.generatorShare)}, ${f(step.generatorUsPerFrame, 2)}, ${f(step.generatorLateP99Ms, 0)} ms | ${pct(step.othersShare)} | ${step.holds ? 'holds' : `fails: ${step.failed.join(', ')}`} |`)
  return [
    `Last run: ${date.toISOString().slice(0, 16).replace('T', ' ')} UTC, ${rooms} rooms, one drop per player every 2 s, ${durationS} s steady phase per step, ${pinned ? `server pinned to CPU 0 and the generator${ledger === 'postgres' ? ' and PostgreSQL' : ''} to CPU 1` : 'NOT pinned'}, ${ledger === 'postgres' ? 'PostgreSQL ledger (flushed on every commit)' : 'SQLite ledger'}, the generator in ${workers === 1 ? 'one worker thread' : `${workers} worker threads`}${steered ? ', the loopback\'s receive processing steered to CPU 1 (--steer-loopback: the generator\'s TCP receive off the server\'s core, and the server\'s own receive of the players\' messages with it)' : ''}.`,
    '',
    `**Most players on one server process with every criterion met${repeated ? ' in every run of the step' : ''}: ${modes.map((mode) => `${mode} ${bestOf(mode)}`).join(', ')}** (criteria: ${CRITERIA.map((c) => c.name).join(', ')}).${repeated ? ` Runs that held, per step: ${runsHeld}.` : ''}`,
    '',
    header,
    `|${header.split('|').slice(1, -1).map(() => ' ---').join(' |')} |`,
    ...rows
  ].join('\n')
}

/** Where this command's table goes in loadtest/RESULTS.md. */
export const CAPACITY_SECTION = Object.freeze({ begin: BEGIN_MARKER, end: END_MARKER, heading: 'Capacity (npm run loadtest:capacity)' })
/** Where a --ledger postgres run's table goes: beside the SQLite one, not over it. */
export const CAPACITY_POSTGRES_SECTION = Object.freeze({
  begin: '<!-- capacity-postgres:begin (written by npm run loadtest:capacity -- --ledger postgres) -->',
  end: '<!-- capacity-postgres:end -->',
  heading: 'Capacity with the ledger in PostgreSQL (npm run loadtest:capacity -- --ledger postgres)'
})

/** Where a --steer-loopback run's table goes (SQLite ledger): beside the default one, not over it. */
export const CAPACITY_STEERED_SECTION = Object.freeze({
  begin: '<!-- capacity-steered:begin (written by npm run loadtest:capacity -- --steer-loopback) -->',
  end: '<!-- capacity-steered:end -->',
  heading: 'Capacity with the loopback\'s receive steered off the server\'s core (npm run loadtest:capacity -- --steer-loopback)'
})

/** The section a run's table goes in. @param {{ ledger: string, steerLoopback?: boolean }} options */
export function capacitySection ({ ledger, steerLoopback = false }) {
  if (ledger === 'postgres') return CAPACITY_POSTGRES_SECTION
  return steerLoopback ? CAPACITY_STEERED_SECTION : CAPACITY_SECTION
}

/**
 * Replaces the text between a section's markers in `file` (or appends the
 * section with them). @param {string} file @param {string} body
 * @param {{ begin: string, end: string, heading: string }} [section]
 */
export function writeBetweenMarkers (file, body, { begin: beginMarker, end: endMarker, heading } = CAPACITY_SECTION) {
  const text = fs.readFileSync(file, 'utf8')
  const begin = text.indexOf(beginMarker)
  const end = text.indexOf(endMarker)
  const block = `${beginMarker}\n${body}\n${endMarker}`
  const next = begin !== -1 && end > begin
    ? text.slice(0, begin) + block + text.slice(end + endMarker.length)
    : `${text.trimEnd()}\n\n## ${heading}\n\n${block}\n`
  fs.writeFileSync(file, next)
}

async function main () {
  const options = optionsOrExit(parseCapacityArgs, process.argv.slice(2), USAGE)
  const pinned = canPin() && pinSelf('1')
  console.log(`capacity: steps ${options.steps.join(', ')}; ${options.rooms} rooms; delivery ${options.deliveries.join(' and ')}; ledger ${options.ledger}; ${pinned ? `server on CPU 0, generator${options.ledger === 'postgres' ? ' and PostgreSQL' : ''} on CPU 1` : 'NOT pinned (no taskset or one CPU)'}${options.steerLoopback ? '; loopback receive on CPU 1' : ''}`)
  if (options.steerLoopback && !pinned) {
    console.error('--steer-loopback needs the server and the generator on CPUs of their own (taskset and two CPUs)')
    process.exit(2)
  }
  let restoreLoopback = null
  if (options.steerLoopback) {
    try {
      restoreLoopback = steerLoopbackReceiveUntilExit(1)
    } catch (error) {
      console.error(error.message)
      process.exit(1)
    }
  }
  // Started after pinning: its processes inherit the generator's CPU.
  const postgres = options.ledger === 'postgres' ? await startPostgres({ durable: true }) : null
  const steps = []
  // Each mode steps on until a step none of whose runs held; the same generator and load for both.
  const stepping = new Set(options.deliveries)
  for (const players of options.steps) {
    if (stepping.size === 0) break
    const floor = options.floorSeconds > 0 ? await measureFloor({ clients: players, seconds: options.floorSeconds, pin: pinned }) : null
    // Run by run, the modes in turn: a slow phase of the machine falls on both alike.
    for (let run = 1; run <= options.repeat; run++) {
      for (const delivery of options.deliveries) {
        if (!stepping.has(delivery)) continue
        const env = postgres ? { DATABASE_URL: await postgres.createDatabase() } : {}
        const ours = await measureOurs({ players, rooms: options.rooms, durationS: options.durationS, rampS: options.rampS, pin: pinned, workers: options.workers, sample: true, delivery, env })
        const step = { ...stepFigures(ours, floor), run }
        steps.push(step)
        console.log(`${players} players, ${delivery}${options.repeat > 1 ? `, run ${run} of ${options.repeat}` : ''}: ${step.holds ? 'holds' : `fails (${step.failed.join(', ')})`}; server ${pct(step.serverShare)} of a core, ${f(step.serverUsPerPlayerSecond, 0)} µs per player-second, ${f(step.serverUsPerDrop, 0)} µs per drop, ${f(step.serverUsPerFrame)} µs/frame (floor ${f(step.floorUsPerFrame)}, ${step.ratio === null ? '–' : f(step.ratio, 2)}×); tick p99 ${f(step.tickP99Ms, 2)} ms, lag p99 ${f(step.lagP99Ms, 2)} ms; commits over 50 ms ${f(step.slowCommits, 0)} (the writer waited for the CPU ${pct(step.writerWaitShare)} of the window); ack p99 ${f(step.ackP99Ms, 0)} ms${delivery === 'seeds' ? `; seen by the room p99 ${f(step.sightingP99Ms, 0)} ms (its frame ${f(step.sightingTicksP99, 0)} ticks after the release, p99)` : ''}; ${f(step.framesPerSecondPerPlayer, 2)} frames/s and ${f(step.bytesPerSecondPerPlayer / 1000, 2)} KB/s per player; generator ${pct(step.generatorShare)}, ${f(step.generatorUsPerFrame, 2)} µs/frame, its loop late p99 ${f(step.generatorLateP99Ms, 0)} ms; others ${pct(step.othersShare)}`)
        if (!ours.summary.passed) console.log(formatLeanSummary(ours.summary))
      }
    }
    // A mode steps on while any run of its step held: the table then shows where it starts to fail.
    if (!options.all) {
      for (const tally of stepTallies(steps)) if (tally.players === players && tally.held === 0) stepping.delete(tally.delivery)
    }
  }
  await postgres?.stop()
  restoreLoopback?.()
  const markdown = capacityMarkdown(steps, { rooms: options.rooms, durationS: options.durationS, pinned, ledger: options.ledger, steered: options.steerLoopback, workers: options.workers })
  console.log(`\n${markdown}`)
  if (options.writeResults) {
    writeBetweenMarkers(RESULTS, markdown, capacitySection(options))
    console.log(`\nwritten to ${path.relative(process.cwd(), RESULTS)}`)
  }
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) await main()
