#!/usr/bin/env node
// Writes docs/engine-spec-vectors.json, the test vectors of docs/engine-spec.md,
// from the JavaScript engine (the reference: where the two disagree, this is right):
//
//   node scripts/engine-spec-vectors.js           # (re)writes the file
//   node scripts/engine-spec-vectors.js --check   # exit 1 if the file is not what the engine gives
//
// Both implementations are tested against the file (tests/spec/): the engine
// must still produce it, and verifier-python must reproduce it.
import { readFileSync, writeFileSync } from 'node:fs'
import { fileURLToPath } from 'node:url'
import { parseArgs } from 'node:util'
import { createBoard, DropSimulator, dropInitialConditions, deriveDropSeed, sha256Hex, ENGINE_VERSIONS, RISKS, MIN_ROWS, MAX_ROWS, StateHasher } from '../engine/index.js'
import { createRandom } from '../engine/random.js'

export const VECTORS_FILE = fileURLToPath(new URL('../docs/engine-spec-vectors.json', import.meta.url))
/** Ticks after which a drop's vector records the ball's state hash. */
export const TRACE_TICKS = [1, 10, 100]
const SERVER_SEED = 'engine-spec-vectors'
const CLIENT_SEED = 'vector'
const SEED_VECTORS = [
  { serverSeed: SERVER_SEED, clientSeed: CLIENT_SEED, nonce: 0 },
  { serverSeed: 'f6d91647a622851ecffa08a3b705ea6dfde317b186c919ac981783fc0a5833b5', clientSeed: 'lucky-7', nonce: 7 },
  { serverSeed: 'ünïcödé €', clientSeed: '', nonce: 9007199254740991 }
]

/** Everything the vectors file holds, computed now by the engine. */
export async function engineSpecVectors () {
  const seeds = []
  for (const seed of SEED_VECTORS) {
    seeds.push({ ...seed, serverSeedHash: await sha256Hex(seed.serverSeed), dropSeed: await deriveDropSeed(seed.serverSeed, seed.clientSeed, seed.nonce) })
  }
  const versions = {}
  for (const version of ENGINE_VERSIONS) versions[version] = await versionVectors(version)
  return {
    comment: 'Test vectors of docs/engine-spec.md, written by `node scripts/engine-spec-vectors.js` from the JavaScript engine. Numbers are IEEE-754 doubles in their shortest round-trip decimal form: parse them as doubles and compare bits.',
    seeds,
    random: ['3480c16c87a4f6f249440ec4f990fb821f945f17d82a7c2323be513c51b10b4d', 'a', 'ü€'].map((seed) => {
      const random = createRandom(seed)
      return { seed, doubles: Array.from({ length: 8 }, () => random()) }
    }),
    stateHash: [[], [0], [-0, 1.5, -2.75e-300, Number.MAX_VALUE, 5e-324, 1 / 3]].map((doubles) => {
      const hasher = new StateHasher()
      for (const value of doubles) hasher.addFloat64(value)
      return { doubles: doubles.map(encodeDouble), hash: hasher.digestHex() }
    }),
    versions
  }
}

/** JSON has no -0: it is written as the string "-0". */
function encodeDouble (value) {
  return Object.is(value, -0) ? '-0' : value
}

async function versionVectors (engineVersion) {
  const boards = [MIN_ROWS, MAX_ROWS].map((rows) => {
    const board = createBoard({ rows, risk: 'medium', engineVersion })
    const grid = new DropSimulator(board).world.staticGrid
    return {
      rows,
      width: board.width,
      pegs: board.pegs.length,
      firstPeg: board.pegs[0],
      lastPeg: board.pegs[board.pegs.length - 1],
      walls: board.walls,
      dropZone: board.dropZone,
      bucketLineY: board.bucketLineY,
      bucketLeftX: board.bucketLeftX,
      bucketWidth: board.bucketWidth,
      grid: { minX: grid._minX, minY: grid._minY, columns: grid._columns, rows: grid._rows, listed: grid.items.length }
    }
  })
  const drops = []
  let nonce = 0
  for (const risk of RISKS) {
    for (let rows = MIN_ROWS; rows <= MAX_ROWS; rows++) {
      const board = createBoard({ rows, risk, engineVersion })
      const dropSeed = await deriveDropSeed(SERVER_SEED, CLIENT_SEED, nonce)
      drops.push({ serverSeed: SERVER_SEED, clientSeed: CLIENT_SEED, nonce, rows, risk, dropSeed, ...traceDrop(board, dropSeed) })
      nonce++
    }
  }
  return { boards, drops }
}

/** The release, the ball's state hash after each of TRACE_TICKS it reaches in flight, and the outcome of one drop. */
function traceDrop (board, dropSeed) {
  const simulator = new DropSimulator(board)
  const body = simulator.addDrop(dropSeed)
  const stateHashAfterTick = {}
  for (let tick = 1; ; tick++) {
    const landed = simulator.step()
    if (landed.length > 0) {
      const { bucket, multiplier, ticks, stateHash } = landed[0]
      return { initial: dropInitialConditions(board, dropSeed), stateHashAfterTick, bucket, multiplier, ticks, stateHash }
    }
    if (TRACE_TICKS.includes(tick)) stateHashAfterTick[tick] = simulator.world.bodyStateHash(body)
  }
}

export async function vectorsText () {
  return JSON.stringify(await engineSpecVectors(), null, 2) + '\n'
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const { values } = parseArgs({ options: { check: { type: 'boolean' } } })
  const text = await vectorsText()
  if (values.check) {
    const same = readFileSync(VECTORS_FILE, 'utf8') === text
    console.log(same ? 'docs/engine-spec-vectors.json is what the engine gives' : 'docs/engine-spec-vectors.json differs from what the engine gives: run node scripts/engine-spec-vectors.js')
    process.exit(same ? 0 : 1)
  }
  writeFileSync(VECTORS_FILE, text)
  console.log('wrote docs/engine-spec-vectors.json')
}
