import os from 'node:os'
import { ENGINE_VERSIONS, createBoard, simulateDrop } from '../engine/index.js'
import { dropSeedSync } from './drop-seeds.js'
import { formatTable, int, fixed } from './text-table.js'

/** The engine's published floor: complete drops per second on one core, 16 rows. */
export const DROPS_PER_SECOND_GOAL = 30000

const SERVER_SEED = 'plinko-bench-server-seed'
const CLIENT_SEED = 'plinko-bench-client-seed'

/**
 * Complete drops per second, seed to landing, on one core: every shipped
 * engine version on 16 and 8 rows, HMAC seeds computed beforehand, then
 * with the HMAC included (as `plinko rtp` and the server run). Needs only
 * the engine: the comparison with matter-js and planck is `npm run bench`.
 * @param {{ quick?: boolean, log?: (line: string) => void }} [options]
 * @returns {{ rows: number, engineVersion: string, hmac: boolean, drops: number, dropsPerSecond: number, ticksPerDrop: number }[]}
 */
export function measureDropThroughput ({ quick = false, log = console.log } = {}) {
  const drops = quick ? 2000 : 20000
  const warmup = quick ? 500 : 3000
  const seeds = Array.from({ length: drops }, (_, nonce) => dropSeedSync(SERVER_SEED, CLIENT_SEED, nonce))
  const figures = []
  for (const rows of [16, 8]) {
    for (const engineVersion of ENGINE_VERSIONS) {
      const board = createBoard({ rows, risk: 'medium', engineVersion })
      for (let i = 0; i < warmup; i++) simulateDrop(board, seeds[i % seeds.length])
      figures.push(timed(rows, engineVersion, false, drops, (i) => simulateDrop(board, seeds[i]).ticks))
      figures.push(timed(rows, engineVersion, true, drops, (i) => simulateDrop(board, dropSeedSync(SERVER_SEED, CLIENT_SEED, i)).ticks))
    }
  }
  log(`Engine throughput${quick ? ' (--quick: short run, figures are rough)' : ''}: complete drops per second on one core, seed to landing`)
  log(`Node ${process.versions.node}, ${os.cpus()[0]?.model ?? 'unknown CPU'}; ${int(drops)} drops per row, ${int(warmup)} warm-up drops first. npm run bench compares with matter-js and planck.`)
  log('')
  log(formatTable([
    { title: 'rows' }, { title: 'engine' }, { title: 'seed', align: 'left' }, { title: 'drops/s' }, { title: 'µs/drop' }, { title: 'ticks/drop' }, { title: 'goal', align: 'left' }
  ], figures.map((f) => [
    String(f.rows), f.engineVersion, f.hmac ? 'HMAC included' : 'precomputed', int(f.dropsPerSecond), fixed(1e6 / f.dropsPerSecond, 1), fixed(f.ticksPerDrop, 1),
    f.rows === 16 && !f.hmac ? `≥${int(DROPS_PER_SECOND_GOAL)} drops/s: ${f.dropsPerSecond >= DROPS_PER_SECOND_GOAL ? 'met' : 'not met'}` : ''
  ])))
  return figures
}

function timed (rows, engineVersion, hmac, drops, simulate) {
  let ticks = 0
  const start = process.hrtime.bigint()
  for (let i = 0; i < drops; i++) ticks += simulate(i)
  const seconds = Number(process.hrtime.bigint() - start) / 1e9
  return { rows, engineVersion, hmac, drops, dropsPerSecond: drops / seconds, ticksPerDrop: ticks / drops }
}
