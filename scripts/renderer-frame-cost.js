#!/usr/bin/env node
/**
 * What the board renderer alone costs a frame, and whether a change to it
 * wins: `node scripts/renderer-frame-cost.js [--against ../old-checkout]
 * [--balls 1,30,100] [--rounds 5] [--seconds 2] [--throttle 1]`.
 *
 * Each tree (this one, and the one `--against` names: another checkout,
 * with `node_modules` linked in) is served by its own server; a page per
 * tree and per size (1366×800, 390×844 DPR 2) loads that tree's
 * client/board-renderer.js and style.css and draws a fixed scene every
 * animation frame: N balls on recorded paths (120 seeds of the 16-row
 * board) with their trails, a peg glow every 25 ticks per ball, a bucket
 * pop on each landing. Only one page draws at a time; the windows
 * alternate between trees (reversed every other round), so a shared
 * machine's load falls on both alike. Prints, per row, the median over the
 * rounds of the main thread's CPU ms per frame (CDP ThreadTime: what other
 * processes barely move, unlike wall-clock time) and its task ms per frame
 * (TaskDuration, what scripts/page-frame-cost.js reports), and fps.
 * Unthrottled by default: CPU time is then the work itself.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { parseArgs } from 'node:util'
import { chromium } from 'playwright-core'
import { createBoard, simulateDrop } from '../engine/index.js'
import { startServerProcess } from '../tools/server-process.js'
import { LIFTED_LIMITS } from '../tools/lifted-limits.js'
import { CHROMIUM_PATH, CHROMIUM_ARGS } from '../tools/chromium.js'

const { values } = parseArgs({
  options: {
    against: { type: 'string' },
    balls: { type: 'string', default: '1,30,100' },
    rounds: { type: 'string', default: '5' },
    seconds: { type: 'string', default: '2' },
    throttle: { type: 'string', default: '1' }
  }
})
const HERE = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')
const TREES = [HERE, ...(values.against ? [path.resolve(values.against)] : [])]
const BALLS = values.balls.split(',').map(Number)
const ROUNDS = Number(values.rounds)
const SECONDS = Number(values.seconds)
const THROTTLE = Number(values.throttle)
const SIZES = [
  { name: '1366×800', options: { viewport: { width: 1366, height: 800 } } },
  { name: '390×844 DPR 2', options: { viewport: { width: 390, height: 844 }, deviceScaleFactor: 2, isMobile: true, hasTouch: true } }
]
const HARNESS = '/__renderer-frame-cost.html'

const board = createBoard({ rows: 16, risk: 'medium' })
const paths = Array.from({ length: 120 }, (_, i) => Array.from(simulateDrop(board, (i * 2654435761 >>> 0).toString(16).padStart(8, '0').repeat(8), { trajectory: true }).trajectory))
const dirs = TREES.map(() => fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-renderer-cost-')))
const servers = TREES.map((root, i) => startServerProcess(`sqlite:${path.join(dirs[i], 'ledger.sqlite')}`, { ...LIFTED_LIMITS }, { root }))
const browser = await chromium.launch({ executablePath: CHROMIUM_PATH, headless: true, args: [...CHROMIUM_ARGS] })
/** @type {Map<string, { cpu: number, task: number, fps: number }[]>} */
const results = new Map()
try {
  const pages = []
  for (const size of SIZES) {
    for (const [i, server] of servers.entries()) pages.push({ size: size.name, tree: i, ...await openHarness(`http://127.0.0.1:${await server.port}`, size.options) })
  }
  for (let round = 0; round < ROUNDS; round++) {
    for (const balls of BALLS) {
      for (const page of round % 2 ? [...pages].reverse() : pages) {
        const key = `${page.size.padEnd(14)}  ${String(balls).padStart(5)}  ${(TREES.length > 1 ? (page.tree === 0 ? 'this tree' : 'against') : '').padEnd(9)}`
        if (!results.has(key)) results.set(key, [])
        results.get(key).push(await measure(page, balls))
      }
    }
  }
} finally {
  await browser.close()
  for (const server of servers) { server.child.kill('SIGTERM'); await server.exited }
  for (const dir of dirs) fs.rmSync(dir, { recursive: true, force: true })
}

console.log(`board renderer alone, headless Chromium, CPU throttled ${THROTTLE}×, ${ROUNDS} rounds of ${SECONDS} s; load average now ${os.loadavg().map((l) => l.toFixed(1)).join(' ')}`)
if (TREES.length > 1) console.log(`this tree: ${TREES[0]}\nagainst:   ${TREES[1]}`)
console.log('viewport        balls  tree       CPU ms/frame (median, each round)         task ms/frame   fps')
for (const [key, rows] of [...results].sort(([a], [b]) => a.localeCompare(b))) {
  const cpu = rows.map((r) => r.cpu)
  console.log(`${key}  ${median(cpu).toFixed(2).padStart(6)}  [${cpu.map((c) => c.toFixed(2)).join(' ')}]   ${median(rows.map((r) => r.task)).toFixed(2).padStart(6)}   ${median(rows.map((r) => r.fps)).toFixed(1).padStart(5)}`)
}

/** A page drawing the scene with one tree's renderer, idle until measured. */
async function openHarness (base, options) {
  const context = await browser.newContext(options)
  const page = await context.newPage()
  await page.route(`${base}${HARNESS}`, (route) => route.fulfill({ contentType: 'text/html', body: harnessHtml() }))
  await page.addInitScript((recorded) => { window.__paths = recorded }, paths)
  await page.goto(`${base}${HARNESS}`)
  await page.waitForFunction(() => window.__bench?.frames > 10)
  await page.evaluate(() => { window.__bench.running = false })
  const cdp = await context.newCDPSession(page)
  await cdp.send('Performance.enable')
  await cdp.send('Emulation.setCPUThrottlingRate', { rate: THROTTLE })
  return { page, cdp }
}

/** One window of `balls` balls on a page: CPU and task ms per frame, fps. */
async function measure ({ page, cdp }, balls) {
  await page.evaluate((n) => { Object.assign(window.__bench, { balls: n, running: true }) }, balls)
  await new Promise((resolve) => setTimeout(resolve, 700))
  const before = await sample(page, cdp)
  await new Promise((resolve) => setTimeout(resolve, SECONDS * 1000))
  const after = await sample(page, cdp)
  await page.evaluate(() => { window.__bench.running = false })
  const frames = after.frames - before.frames
  return { cpu: (after.cpu - before.cpu) * 1000 / frames, task: (after.task - before.task) * 1000 / frames, fps: frames / ((after.at - before.at) / 1000) }
}

async function sample (page, cdp) {
  const { metrics } = await cdp.send('Performance.getMetrics')
  const metric = (name) => metrics.find((m) => m.name === name).value
  return { at: performance.now(), frames: await page.evaluate(() => window.__bench.frames), cpu: metric('ThreadTime'), task: metric('TaskDuration') }
}

function median (values) {
  const sorted = [...values].sort((a, b) => a - b)
  return sorted[Math.floor(sorted.length / 2)]
}

/** The page: the player page's board markup and stylesheet, the tree's renderer, the scene drawn each frame while running. */
function harnessHtml () {
  return `<!doctype html><html><head><meta name="viewport" content="width=device-width, initial-scale=1">
<script type="importmap">{"imports":{"seedrandom":"/vendor/seedrandom.js"}}</script>
<link rel="stylesheet" href="/style.css"></head>
<body class="player"><main><section class="stage"><div class="canvas-wrap board-wrap"><canvas id="board"></canvas></div></section></main>
<script type="module">
import { BoardRenderer } from '/board-renderer.js'
import { createBoard } from '/engine/index.js'
const renderer = new BoardRenderer(document.getElementById('board'), { maxHeight: () => innerHeight - 88 })
const board = createBoard({ rows: 16, risk: 'medium' })
renderer.setBoard(board)
const paths = window.__paths.map((p) => Float64Array.from(p))
const bench = window.__bench = { frames: 0, balls: 1, running: true }
let tick = 0
function frame (now) {
  requestAnimationFrame(frame)
  if (!bench.running) return
  tick++
  const poses = []
  for (let i = 0; i < bench.balls; i++) {
    const t = paths[i % paths.length]
    const ticks = t.length / 3
    const age = (tick + Math.floor(i * 187 / bench.balls)) % ticks
    const mine = i % 10 === 0
    poses.push({ x: t[3 * age], y: t[3 * age + 1], angle: t[3 * age + 2], alpha: age > ticks - 10 ? (ticks - age) / 10 : 1, mine, trajectory: t, age, ox: 0, oy: 0 })
    if (age % 25 === 0) renderer.glowPeg((i * 13 + age) % board.pegs.length, mine, now)
    if (age === ticks - 1) renderer.flash(i % board.multipliers.length, mine, now)
  }
  renderer.draw(poses, now)
  bench.frames++
}
requestAnimationFrame(frame)
</script></body></html>`
}
