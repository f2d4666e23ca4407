#!/usr/bin/env node
/**
 * `npm run bench` (node bench/run.js [--quick] [--only engine|game|server|floor]).
 *
 * Runs the engine benchmarks (engine-bench.js: our engine, matter-js and
 * planck, in this one process so the peers are measured in the same run),
 * the game figures of every engine version (game-figures.js: distribution,
 * volatility, fall, RTP), then the server benchmarks bench/server-ticks.js and
 * bench/server-snapshots.js when they exist, each as a child process
 * `node --expose-gc <file> [--quick]` whose output is passed through
 * (stopped after SERVER_BENCH_TIMEOUT_S, so a hung bench cannot hang the run),
 * then the WebSocket floor beside our server (bench/ws-floor.js, part
 * `floor`: a bare `ws` server's CPU per frame and ours under the lean load
 * generator, pinned to one core each, and their ratio), the same way.
 *
 * --quick: a short run (CI smoke tests); the figures are rough.
 *
 * The heap table needs a forced GC: without --expose-gc this script
 * re-runs itself with it. Exit code 0 whatever the figures; non-zero only
 * when a benchmark crashes (or 2 for a bad argument).
 */
import { spawnSync } from 'node:child_process'
import { existsSync } from 'node:fs'
import { fileURLToPath } from 'node:url'
import { parseArgs } from 'node:util'
import { runEngineBenchmarks } from './engine-bench.js'
import { runGameFigures } from './game-figures.js'

const SERVER_BENCHES = ['server-ticks.js', 'server-snapshots.js']
const FLOOR_BENCHES = ['ws-floor.js']
/** A server bench that runs longer than this is stopped (SIGTERM) and reported as failed, so `npm run bench` never hangs. */
const SERVER_BENCH_TIMEOUT_S = { quick: 180, full: 900 }
const USAGE = 'usage: node bench/run.js [--quick] [--only engine|game|server|floor]'
const PARTS = ['engine', 'game', 'server', 'floor']

const args = process.argv.slice(2)
let options
try {
  options = parseArgs({ args, options: { quick: { type: 'boolean' }, only: { type: 'string' }, help: { type: 'boolean', short: 'h' } } }).values
  if (options.only !== undefined && !PARTS.includes(options.only)) throw new Error(`--only must be one of ${PARTS.join(', ')}`)
} catch (error) {
  console.error(`${error.message}\n${USAGE}`)
  process.exit(2)
}
if (options.help) {
  console.log(USAGE)
  process.exit(0)
}
const quick = Boolean(options.quick)
const runs = (part) => options.only === undefined || options.only === part

if (typeof globalThis.gc !== 'function') {
  const child = spawnSync(process.execPath, ['--expose-gc', ...process.execArgv, fileURLToPath(import.meta.url), ...args], { stdio: 'inherit' })
  process.exit(child.status ?? 1)
}

if (runs('engine')) await runEngineBenchmarks({ quick })
if (runs('game')) {
  console.log('')
  await runGameFigures({ quick })
}

for (const file of [...(runs('server') ? SERVER_BENCHES : []), ...(runs('floor') ? FLOOR_BENCHES : [])]) {
  const path = fileURLToPath(new URL(file, import.meta.url))
  console.log('')
  if (!existsSync(path)) {
    console.log(`== bench/${file}: not present, skipped ==`)
    continue
  }
  console.log(`== bench/${file} ==`)
  const timeout = SERVER_BENCH_TIMEOUT_S[quick ? 'quick' : 'full']
  const child = spawnSync(process.execPath, ['--expose-gc', path, ...(quick ? ['--quick'] : [])], { stdio: 'inherit', timeout: timeout * 1000 })
  if (child.status !== 0) {
    const why = child.error?.code === 'ETIMEDOUT'
      ? `did not finish within ${timeout} s, stopped`
      : child.error?.message ?? (child.signal ? `killed by ${child.signal}` : `exit code ${child.status}`)
    console.log(`bench/${file} failed: ${why}`)
    process.exitCode = 1
  }
}
