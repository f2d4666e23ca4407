#!/usr/bin/env node
// One drop, tick by tick, from the JavaScript engine: a JSON line per tick
// with the ball's state and its state hash (docs/engine-spec.md, section 10),
// the last line its outcome. `plinko-verify trace` (verifier-python) prints
// the same lines, so an implementation of the spec that differs can diff its
// own trace against these and find the first tick, and value, that differs:
//
//   node scripts/trace-drop.js --drop-seed S [--rows 16] [--risk medium] [--engine-version V]
import { fileURLToPath } from 'node:url'
import { createBoard, DropSimulator } from '../engine/index.js'
import { parseCommandLine } from '../cli/command-line.js'
import { optionsOrExit } from '../cli/usage-error.js'
import { rowsOption, riskOption, requiredString, engineVersionOption } from '../cli/options.js'

const USAGE = 'usage: node scripts/trace-drop.js --drop-seed S [--rows 16] [--risk medium] [--engine-version V]'

/** Yields the JSON-ready lines of one drop's trace: the ball after every tick in flight, then the outcome. */
export function * traceDrop (board, dropSeed) {
  const simulator = new DropSimulator(board)
  const body = simulator.addDrop(dropSeed)
  const world = simulator.world
  for (let tick = 1; ; tick++) {
    const landed = simulator.step()
    if (landed.length > 0) {
      const { bucket, multiplier, ticks, stateHash } = landed[0]
      yield { tick, landed: true, bucket, multiplier, ticks, stateHash }
      return
    }
    yield {
      tick,
      x: world.xOf(body),
      y: world.yOf(body),
      vx: world.vxOf(body),
      vy: world.vyOf(body),
      angle: world.angleOf(body),
      spin: world.angularVelocityOf(body),
      stateHash: world.bodyStateHash(body)
    }
  }
}

function parse (argv) {
  const options = parseCommandLine(argv, {
    help: { type: 'boolean', short: 'h' },
    'drop-seed': { type: 'string' },
    rows: { type: 'string' },
    risk: { type: 'string' },
    'engine-version': { type: 'string' }
  })
  if (options.help) return options
  return {
    dropSeed: requiredString(options['drop-seed'], 'drop-seed'),
    board: { rows: rowsOption(options.rows), risk: riskOption(options.risk), engineVersion: engineVersionOption(options['engine-version']) }
  }
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const { dropSeed, board } = optionsOrExit(parse, process.argv.slice(2), USAGE)
  process.stdout.on('error', () => process.exit(0)) // piped into head: stop quietly
  for (const line of traceDrop(createBoard(board), dropSeed)) process.stdout.write(JSON.stringify(line) + '\n')
}
