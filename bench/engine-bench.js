/**
 * The engine benchmarks, as a function for `npm run bench` (bench/run.js)
 * and the `plinko bench` CLI command:
 *
 *   import { runEngineBenchmarks } from './bench/engine-bench.js'
 *   const figures = await runEngineBenchmarks({ quick: false, log: console.log })
 *
 * Prints three tables through `log` (one line per call) and returns the
 * figures: { quick, environment, scene, allocation, drops } (see the
 * typedefs below). It sets no thresholds and never fails on a figure: the
 * goals are printed beside the numbers.
 *
 * 1. 100-ball scene: time per step of the same scene in our engine,
 *    matter-js and planck, measured in the same process, interleaved.
 * 2. Allocation: heap growth of our engine's 100-ball scene over 100,000
 *    steps (10,000 with quick), after forced GCs. Needs a forced GC: run
 *    Node with --expose-gc (bench/run.js does); without it the function
 *    asks V8 for one at run time and skips the table if that fails.
 * 3. Single drop: complete drops per second on one core, seed to landing,
 *    16 and 8 rows, our simulateDrop() beside one-ball runs of the peers.
 */
import { readFileSync } from 'node:fs'
import os from 'node:os'
import { ENGINE_VERSION, ENGINE_VERSIONS, simulateDrop } from '../engine/index.js'
import { dropSeedSync } from '../cli/drop-seeds.js'
import { SCENE, BALL_MATERIAL, PEG_MATERIAL, BENCH_SERVER_SEED, BENCH_CLIENT_SEED, benchDropSeeds, startTable, sceneBoard } from './plinko-scene.js'
import { OursScene, OursServerScene } from './scene-ours.js'
import { MatterScene, MATTER_WALL_THICKNESS } from './scene-matter.js'
import { PlanckScene, PLANCK_VELOCITY_ITERATIONS, PLANCK_POSITION_ITERATIONS } from './scene-planck.js'
import { timeStepsInterleaved, summarize, timeMs, findGc, heapGrowth } from './measure.js'
import { formatTable, int, fixed, ratio, bytes } from '../cli/text-table.js'
import { mixFriction, mixRestitution } from '../engine/materials.js'

export const GOALS = Object.freeze({ vsMatter: 20, vsPlanck: 5, dropsPerSecond: 30000 })

/** How much each benchmark runs. */
export const FULL_RUN = Object.freeze({
  sceneWarmup: 2000,
  sceneSteps: 20000,
  sceneBlock: 1000,
  heapSteps: 100000,
  /** steps before the heap is measured, so the JIT's code is compiled (it lives on the heap too) */
  heapWarmup: 5000,
  /** simulateDrop calls measured for allocation per drop (few: a drop allocates kilobytes, and a GC would blur the figure) */
  heapDrops: 200,
  dropWarmup: 3000,
  drops: 30000,
  peerDropWarmup: 20,
  peerDrops: 500,
  dropRows: [16, 8],
  /** distinct start conditions the 100-ball scenes cycle through */
  sceneStarts: 1000
})

export const QUICK_RUN = Object.freeze({
  sceneWarmup: 400, // past the release ramp (100 balls × 3 ticks)
  sceneSteps: 1000,
  sceneBlock: 250,
  heapSteps: 10000,
  heapWarmup: 3000,
  heapDrops: 200,
  dropWarmup: 500,
  drops: 3000,
  peerDropWarmup: 5,
  peerDrops: 30,
  dropRows: [16, 8],
  sceneStarts: 1000
})

const MATTER_VERSION = packageVersion('matter-js')
const PLANCK_VERSION = packageVersion('planck')

/**
 * @typedef {object} StepFigures
 * @property {string} engine @property {number} mean µs @property {number} p50 µs @property {number} p99 µs @property {number} max µs
 * @property {number} drops drops completed over warm-up and timed steps @property {number} ticksPerDrop
 * @property {boolean} peer matter-js or planck (false: a row of ours)
 * @property {number | null} oursFasterBy for a peer: its mean / ours (World.step) mean
 * @property {number | null} oursFasterByP50 the same for p50
 * @property {number | null} goal
 */
/**
 * @typedef {object} DropFigures
 * @property {number} rows @property {string} engine @property {number} drops
 * @property {number} dropsPerSecond @property {number} ticksPerDrop
 * @property {boolean} peer @property {number | null} goal
 * @property {number | null} oursFasterBy for a peer: ours (simulateDrop) drops/s / its drops/s
 */

/**
 * @param {{ quick?: boolean, log?: (line: string) => void }} [options]
 * @returns {Promise<{ quick: boolean, environment: object, scene: StepFigures[], allocation: object[] | null, drops: DropFigures[] }>}
 */
export async function runEngineBenchmarks ({ quick = false, log = console.log } = {}) {
  const run = quick ? QUICK_RUN : FULL_RUN
  const gc = findGc()
  const environment = describeEnvironment()
  log(`Engine benchmarks${quick ? ' (--quick: short run, figures are rough)' : ''}`)
  log(`Node ${environment.node} (V8 ${environment.v8}), ${environment.platform}, ${environment.cpu} × ${environment.cores}, load average ${environment.loadAverage}`)
  log(`engine ${ENGINE_VERSION} (scenes; single drops under every version: ${ENGINE_VERSIONS.join(', ')}), matter-js ${MATTER_VERSION}, planck ${PLANCK_VERSION}`)
  log('')
  const scene = benchScene(run, gc, log)
  log('')
  const allocation = await benchAllocation(run, gc, log)
  log('')
  const drops = benchDrops(run, gc, log)
  return { quick, environment, scene, allocation, drops }
}

// ---- 1. 100-ball scene ---------------------------------------------------

function benchScene (run, gc, log) {
  const board = sceneBoard()
  const seeds = benchDropSeeds(run.sceneStarts)
  const starts = startTable(board, seeds)
  const engines = [
    { engine: 'ours (World.step)', scene: new OursScene(board, starts), peer: false, goal: null },
    { engine: 'ours (DropSimulator, server path)', scene: new OursServerScene(board, seeds), peer: false, goal: null },
    { engine: `matter-js ${MATTER_VERSION}`, scene: new MatterScene(board, starts), peer: true, goal: GOALS.vsMatter },
    { engine: `planck ${PLANCK_VERSION}`, scene: new PlanckScene(board, starts), peer: true, goal: GOALS.vsPlanck },
    { engine: `planck ${PLANCK_VERSION}, continuous off (*)`, scene: new PlanckScene(board, starts, { continuousPhysics: false }), peer: true, goal: null }
  ]
  const samples = timeStepsInterleaved(engines.map((e) => e.scene), { warmup: run.sceneWarmup, steps: run.sceneSteps, block: run.sceneBlock, gc })
  const figures = engines.map(({ engine, scene }, i) => ({
    engine,
    ...summarize(samples[i]),
    drops: scene.landed,
    ticksPerDrop: scene.landedTicks / scene.landed
  }))
  const ours = figures[0]
  for (const [i, f] of figures.entries()) {
    const peer = engines[i].peer
    f.peer = peer
    f.oursFasterBy = peer ? f.mean / ours.mean : null
    f.oursFasterByP50 = peer ? f.p50 / ours.p50 : null
    f.goal = engines[i].goal
  }

  const surface = `restitution ${mixRestitution(BALL_MATERIAL.restitution, PEG_MATERIAL.restitution)}, friction ${fixed(mixFriction(BALL_MATERIAL.friction, PEG_MATERIAL.friction), 3)}`
  log(`== 1. 100-ball scene: time per step (${SCENE.rows} rows) ==`)
  log(`Board createBoard({ rows: ${SCENE.rows}, risk: '${SCENE.risk}', engineVersion: '${SCENE.engineVersion}' }): ${board.pegs.length} static pegs (r ${board.pegRadius} px), ${board.walls.length} static walls;`)
  log(`${SCENE.balls} dynamic balls (r ${board.ballRadius} px) in flight, released ${SCENE.releaseEvery} ticks apart from the drop zone, respawned at the top`)
  log(`once past the bucket line (y > ${board.bucketLineY} px) or after ${SCENE.maxTicks} ticks. Starts from dropInitialConditions() of ${int(run.sceneStarts)} HMAC drop seeds, same order in every engine.`)
  log(`Step 1/60 s everywhere; gravity ${SCENE.gravity} px/s² (planck: ${SCENE.gravity / SCENE.pixelsPerMetre} m/s², 1 m = ${SCENE.pixelsPerMetre} px); ball on peg/wall: ${surface}.`)
  log('Balls do not collide with each other: ours collidesWithBodies: false (as DropSimulator creates them),')
  log('matter-js collisionFilter.group -1, planck filterGroupIndex -1.')
  log(`matter-js: Engine.update(engine, 1000/60), default iterations, circles are 10-gons, walls ${MATTER_WALL_THICKNESS} px rectangles. planck: world.step(1/60, ${PLANCK_VELOCITY_ITERATIONS}, ${PLANCK_POSITION_ITERATIONS}).`)
  log(`${int(run.sceneSteps)} timed steps per engine after ${int(run.sceneWarmup)} warm-up steps, interleaved in blocks of ${int(run.sceneBlock)}${gc ? ', GC forced between blocks (untimed)' : ''}.`)
  log('')
  log(formatTable([
    { title: 'engine', align: 'left' }, { title: 'mean µs/step' }, { title: 'p50 µs' }, { title: 'p99 µs' }, { title: 'max µs' },
    { title: 'drops' }, { title: 'ticks/drop' }, { title: 'ours faster (mean)' }, { title: 'ours faster (p50)' }, { title: 'goal', align: 'left' }
  ], figures.map((f) => [
    f.engine, fixed(f.mean, 2), fixed(f.p50, 2), fixed(f.p99, 2), fixed(f.max, 1), int(f.drops), fixed(f.ticksPerDrop, 1),
    f.oursFasterBy === null ? '-' : ratio(f.oursFasterBy),
    f.oursFasterByP50 === null ? '-' : ratio(f.oursFasterByP50),
    f.goal === null ? '' : `≥${f.goal}×: ${f.oursFasterBy >= f.goal ? 'met' : 'not met'}`
  ])))
  log('"ours faster" = that engine\'s time per step / ours (World.step). drops / ticks per drop: over warm-up and timed steps, a check that')
  log('the scenes do the same work. ours (DropSimulator) also draws each start with seedrandom and records each landing.')
  log('(*) reference, not a goal: planck with continuous collision (time of impact) off, its default being on; without it a fast ball')
  log('can pass through a thin shape, which our engine is built (and tested) never to allow.')
  return figures
}

// ---- 2. allocation -------------------------------------------------------

async function benchAllocation (run, gc, log) {
  log(`== 2. Allocation: heap over ${int(run.heapSteps)} steps of our 100-ball scene, and per drop ==`)
  if (!gc) {
    log('skipped: no forced GC available; run with `node --expose-gc bench/run.js` (npm run bench does).')
    return null
  }
  const board = sceneBoard()
  const seeds = benchDropSeeds(run.sceneStarts)
  const starts = startTable(board, seeds)
  const scene = new OursScene(board, starts)
  const server = new OursServerScene(board, seeds)
  const dropSeeds = benchDropSeeds(run.heapDrops + run.dropWarmup, 2_000_000)
  let nextDrop = 0
  const subjects = [
    { what: 'ours World.step + respawn (scene above)', unit: 'step', count: run.heapSteps, warmup: run.heapWarmup, run: () => scene.step() },
    { what: 'ours DropSimulator.step + addDrop (server path)', unit: 'step', count: run.heapSteps, warmup: run.heapWarmup, run: () => server.step() },
    { what: 'ours simulateDrop(board, seed), per drop', unit: 'drop', count: run.heapDrops, warmup: run.dropWarmup, run: () => simulateDrop(board, dropSeeds[nextDrop++]) }
  ]
  const figures = []
  for (const { what, unit, count, warmup, run: once } of subjects) {
    for (let i = 0; i < warmup; i++) once()
    const growth = await heapGrowth(once, count, gc)
    figures.push({ what, unit, ...growth })
  }
  log('Used V8 heap after a forced GC, right after the run (no GC), and after a forced GC again; "GCs" counts collections V8 ran')
  log('by itself during the run. With no GC during the run, "allocated B/unit" is what each step (or drop) allocated, give or take')
  log('a few bytes of the JIT\'s own work; "retained" is what stays after a full GC. Warm-up steps (drops) first.')
  log('')
  log(formatTable([
    { title: 'what', align: 'left' }, { title: 'unit', align: 'left' }, { title: 'count' }, { title: 'heap before' }, { title: 'after run' }, { title: 'after GC' },
    { title: 'GCs' }, { title: 'allocated B/unit' }, { title: 'retained B/unit' }
  ], figures.map((f) => [
    f.what, f.unit, int(f.steps), bytes(f.before), bytes(f.afterRun), bytes(f.afterGc), int(f.collectionsDuringRun),
    f.allocatedPerStep === null ? 'n/a (GC ran)' : fixed(f.allocatedPerStep, 2), fixed(f.retainedPerStep, 3)
  ])))
  return figures
}

// ---- 3. single drop ------------------------------------------------------

function benchDrops (run, gc, log) {
  const figures = []
  for (const rows of run.dropRows) {
    const seeds = benchDropSeeds(run.drops)
    const warmupSeeds = benchDropSeeds(run.dropWarmup, 1_000_000)
    // Older versions' boards first: drops they decided still re-simulate (audits, verification).
    for (const version of ENGINE_VERSIONS.filter((v) => v !== ENGINE_VERSION)) {
      const old = sceneBoard(rows, version)
      for (const seed of warmupSeeds) simulateDrop(old, seed)
      if (gc) gc()
      let oldTicks = 0
      const oldMs = timeMs(() => {
        for (let i = 0; i < seeds.length; i++) oldTicks += simulateDrop(old, seeds[i]).ticks
      })
      figures.push({ rows, engine: `ours simulateDrop, engine ${version}`, peer: false, drops: seeds.length, dropsPerSecond: seeds.length / oldMs * 1000, ticksPerDrop: oldTicks / seeds.length, goal: GOALS.dropsPerSecond })
    }
    const board = sceneBoard(rows)
    for (const seed of warmupSeeds) simulateDrop(board, seed)
    if (gc) gc()
    let ticks = 0
    let ms = timeMs(() => {
      for (let i = 0; i < seeds.length; i++) ticks += simulateDrop(board, seeds[i]).ticks
    })
    figures.push({ rows, engine: `ours simulateDrop(board, seed), engine ${ENGINE_VERSION}`, newest: true, peer: false, drops: seeds.length, dropsPerSecond: seeds.length / ms * 1000, ticksPerDrop: ticks / seeds.length, goal: GOALS.dropsPerSecond })

    if (gc) gc()
    ticks = 0
    ms = timeMs(() => {
      for (let nonce = 0; nonce < seeds.length; nonce++) ticks += simulateDrop(board, dropSeedSync(BENCH_SERVER_SEED, BENCH_CLIENT_SEED, nonce)).ticks
    })
    figures.push({ rows, engine: 'ours HMAC seed + simulateDrop', peer: false, drops: seeds.length, dropsPerSecond: seeds.length / ms * 1000, ticksPerDrop: ticks / seeds.length, goal: null })

    const peerStarts = startTable(board, seeds.slice(0, run.peerDrops))
    const warmupStarts = startTable(board, warmupSeeds.slice(0, run.peerDropWarmup))
    for (const [engine, Scene] of [[`matter-js ${MATTER_VERSION}`, MatterScene], [`planck ${PLANCK_VERSION}`, PlanckScene]]) {
      const warm = new Scene(board, warmupStarts, { balls: 1 })
      while (warm.landed < run.peerDropWarmup) warm.step()
      const scene = new Scene(board, peerStarts, { balls: 1 })
      if (gc) gc()
      ms = timeMs(() => { while (scene.landed < run.peerDrops) scene.step() })
      figures.push({ rows, engine, peer: true, drops: scene.landed, dropsPerSecond: scene.landed / ms * 1000, ticksPerDrop: scene.landedTicks / scene.landed, goal: null })
    }
  }
  for (const f of figures) {
    const ours = figures.find((o) => o.rows === f.rows && o.newest)
    f.oursFasterBy = f.peer ? ours.dropsPerSecond / f.dropsPerSecond : null
  }

  log('== 3. Single drop: complete drops per second on one core, seed to landing ==')
  log(`ours: simulateDrop(board, dropSeed) with ${int(run.drops)} HMAC drop seeds computed beforehand (second row: HMAC included, as \`plinko rtp\` runs);`)
  log(`${int(run.dropWarmup)} warm-up drops first. matter-js / planck: one ball on the same board from the same starts as the first`)
  log(`${int(run.peerDrops)} of those seeds (start drawn beforehand), stepped at 1/60 s until it passes the bucket line; ${run.peerDropWarmup} warm-up drops.`)
  log('')
  log(formatTable([
    { title: 'rows' }, { title: 'engine', align: 'left' }, { title: 'drops' }, { title: 'drops/s' }, { title: 'µs/drop' },
    { title: 'ticks/drop' }, { title: 'ours faster' }, { title: 'goal', align: 'left' }
  ], figures.map((f) => [
    String(f.rows), f.engine, int(f.drops), int(f.dropsPerSecond), fixed(1e6 / f.dropsPerSecond, 1), fixed(f.ticksPerDrop, 1),
    f.oursFasterBy === null ? '-' : ratio(f.oursFasterBy),
    f.goal === null ? '' : `≥${int(f.goal)} drops/s: ${f.dropsPerSecond >= f.goal ? 'met' : 'not met'}`
  ])))
  log('"ours faster" = ours simulateDrop drops/s / that engine\'s drops/s, same rows.')
  return figures
}

// ---- environment ---------------------------------------------------------

function describeEnvironment () {
  const cpus = os.cpus()
  return {
    node: process.versions.node,
    v8: process.versions.v8,
    platform: `${process.platform} ${process.arch}`,
    cpu: cpus[0]?.model?.trim() ?? 'unknown CPU',
    cores: cpus.length,
    loadAverage: os.loadavg().map((l) => l.toFixed(2)).join(' ')
  }
}

function packageVersion (name) {
  try {
    return JSON.parse(readFileSync(new URL(`../node_modules/${name}/package.json`, import.meta.url), 'utf8')).version
  } catch {
    return '(version unknown)'
  }
}
