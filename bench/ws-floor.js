#!/usr/bin/env node
/**
 * The WebSocket floor beside our server, in one run:
 * `node bench/ws-floor.js [--quick] [--players N] [--seconds S] [--repeat R]`
 * (part `floor` of `npm run bench`).
 *
 * 1. **The floor**: bench/ws-floor-server.js, a bare `ws` server that only
 *    sends the same 190-byte binary frame to every socket every 50 ms
 *    (perMessageDeflate off, no game, no ledger), pinned to CPU 0
 *    (`taskset -c 0`), with N raw clients (loadtest/lean/lean-socket.js) in
 *    this process on CPU 1. Its CPU time (/proc/<pid>/stat) over the window,
 *    divided by the frames the clients received: the floor's µs per frame.
 * 2. **Ours**: server/server.js (fresh SQLite ledger, per-address limits
 *    lifted), pinned to CPU 0, under the lean load generator with the
 *    reference load (N players, 100 rooms, one drop each every 2 s, 20 Hz
 *    snapshots) on CPU 1: the server's CPU over the generator's steady
 *    window, divided by the frames its players received (room frames and
 *    their own `dropped`/`settled`).
 *
 * Printed side by side: both µs per frame and their ratio (goal ≤ 1.5×),
 * and the generator's own µs per frame beside the bare clients' (the
 * floor of a reader on this kernel); each with the part of it spent in
 * the kernel (system time), and what the ratio goal leaves for the rest.
 * Without taskset (or with one CPU) the processes are not pinned and the
 * figures say so. The machine may be
 * shared: the other processes' CPU over each window is printed too.
 * Exit code 0 whatever the figures; 1 when a run's checks fail.
 */
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { parseArgs } from 'node:util'
import { formatLeanSummary } from '../loadtest/lean/lean-generator.js'
import { canPin, pinSelf, measureFloor, measureOurs } from '../loadtest/lean/measure-server.js'
import { formatTable, fixed } from '../cli/text-table.js'

const GOAL_RATIO = 1.5

const pct = (share) => share === null || share === undefined ? '–' : `${(share * 100).toFixed(1)}%`
const spread = (values, digits = 2) => values.length < 2 ? fixed(values[0], digits) : `${fixed(Math.min(...values), digits)}–${fixed(Math.max(...values), digits)}`

async function main () {
  const USAGE = 'usage: node bench/ws-floor.js [--quick] [--players N] [--seconds S] [--repeat R]'
  let values
  try {
    values = parseArgs({ options: { quick: { type: 'boolean' }, players: { type: 'string' }, seconds: { type: 'string' }, repeat: { type: 'string' }, help: { type: 'boolean', short: 'h' } } }).values
  } catch (error) {
    console.error(`${error.message}\n${USAGE}`)
    process.exit(2)
  }
  if (values.help) return console.log(USAGE)
  const quick = Boolean(values.quick)
  const players = Number(values.players ?? (quick ? 200 : 1000))
  const seconds = Number(values.seconds ?? (quick ? 5 : 20))
  const repeat = Number(values.repeat ?? 1)
  if (![players, seconds, repeat].every((n) => Number.isFinite(n) && n > 0)) {
    console.error(USAGE)
    process.exit(2)
  }
  const pin = canPin() && pinSelf('1')
  console.log(`WebSocket floor vs our server: ${players} clients / players, ${seconds} s windows, ${repeat} run${repeat > 1 ? 's' : ''}; ${pin ? 'server on CPU 0, clients and generator on CPU 1 (taskset)' : 'NOT pinned (no taskset or one CPU): the figures share cores'}`)
  const rows = []
  /** One entry per run: µs per frame of each side, whole and in the kernel. */
  const runs = []
  for (let run = 1; run <= repeat; run++) {
    const floor = await measureFloor({ clients: players, seconds, pin })
    const our = await measureOurs({ players, durationS: seconds + 3, rampS: quick ? 3 : 10, pin })
    const figures = {
      floor: floor.serverUsPerFrame,
      floorKernel: floor.serverKernelUsPerFrame,
      ours: our.serverUsPerFrame,
      oursKernel: our.serverKernelUsPerFrame,
      ratio: our.serverUsPerFrame / floor.serverUsPerFrame,
      reader: floor.clientUsPerFrame,
      readerKernel: floor.clientKernelUsPerFrame,
      generator: our.summary.cpu.usPerFrame,
      generatorKernel: our.summary.cpu.usPerFrame - our.summary.cpu.userUsPerFrame
    }
    runs.push(figures)
    rows.push([`${run}: floor (bare ws, 190 B every 50 ms)`, fixed(floor.framesPerSecond, 0), pct(floor.serverShare), fixed(figures.floor, 2), fixed(figures.floorKernel, 2), '1.00×', `${fixed(figures.reader, 2)} (${fixed(figures.readerKernel, 2)} kernel), bare reader`, pct(floor.othersShare)])
    rows.push([`${run}: ours (${players} players, 100 rooms, 1 drop / 2 s)`, fixed(our.framesPerSecond, 0), pct(our.serverShare), fixed(figures.ours, 2), fixed(figures.oursKernel, 2), `${fixed(figures.ratio, 2)}×`, `${fixed(figures.generator, 2)} (${fixed(figures.generatorKernel, 2)} kernel), lean generator`, pct(our.othersShare)])
    if (!our.summary.passed) {
      console.log(formatLeanSummary(our.summary))
      process.exitCode = 1
    }
  }
  const all = (read) => spread(runs.map(read))
  const worst = (read) => Math.max(...runs.map(read))
  const columns = ['run: what', 'frames/s', 'server CPU', 'server µs/frame', 'of which kernel', 'vs floor', 'client µs/frame', 'other processes'].map((title, i) => ({ title, align: i === 0 || i === 6 ? 'left' : 'right' }))
  console.log(formatTable(columns, rows))
  console.log(`server µs per frame: floor ${all((r) => r.floor)}, ours ${all((r) => r.ours)}; ours / floor = ${all((r) => r.ratio)}× (goal ≤ ${GOAL_RATIO}×: ${worst((r) => r.ratio) <= GOAL_RATIO ? 'met' : 'not met'})`)
  console.log(`  of which in the kernel: floor ${all((r) => r.floorKernel)}, ours ${all((r) => r.oursKernel)}; the goal leaves ours ${all((r) => GOAL_RATIO * r.floor - r.oursKernel)} µs per frame of user time (the floor's own user time: ${all((r) => r.floor - r.floorKernel)})`)
  console.log(`client µs per frame received: bare reader ${all((r) => r.reader)}, lean generator ${all((r) => r.generator)} (goal ≤ 5 µs: ${worst((r) => r.generator) <= 5 ? 'met' : 'not met'})`)
  console.log(`  of which in the kernel: bare reader ${all((r) => r.readerKernel)}, lean generator ${all((r) => r.generatorKernel)}`)
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) await main()
