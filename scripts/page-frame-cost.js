#!/usr/bin/env node
/**
 * What drawing a busy room costs the player page:
 * `node scripts/page-frame-cost.js [--seconds 10] [--delivery seeds,snapshots] [--board worker|main] [--simulation main,worker]`.
 *
 * Starts the real server (SQLite in a temporary folder), opens the player
 * page in headless Chromium (CHROMIUM_PATH, default /usr/bin/chromium)
 * with the CPU slowed 4× (CDP Emulation.setCPUThrottlingRate: a mid-range
 * phone), and has bot players in the same room drop balls at the rate that
 * keeps 30, then 100, of them in flight (the mean flight time of the
 * room's board, from the engine). Over a steady window it reads the
 * page's main-thread time (CDP Performance.getMetrics TaskDuration: every
 * task — the frame's simulation and drawing, the canvas's rasterisation,
 * socket messages, garbage collection; ScriptDuration: JavaScript alone)
 * and the frames drawn, and prints main-thread ms per animation frame, the
 * JavaScript part of it, the seeds simulation's part (SeededRoom.posesAt:
 * stepping every ball and its pose) and frames per second, at 1366×800
 * and at 390×844 (DPR 2, mobile), in both delivery modes. The board is
 * drawn in a worker (OffscreenCanvas), whose time is not the main
 * thread's; frames are those the worker drew. `--board main` draws it on
 * the main thread instead (the page's fallback, `?board=main`).
 * `--simulation main,worker` measures a seeds room simulated on the main
 * thread (`?simulation=main`) and in the board worker (the default page)
 * side by side, one after the other for each size and ball count; for a
 * room simulated in the worker, the simulation column is the worker's own
 * time (its SeededRoom's counters), not the main thread's.
 * Figures go to docs/client.md.
 */
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { chromium } from 'playwright-core'
import { createBoard, simulateDrop } from '../engine/index.js'
import { startServerProcess } from '../tools/server-process.js'
import { LIFTED_LIMITS } from '../tools/lifted-limits.js'
import { CHROMIUM_PATH, CHROMIUM_ARGS } from '../tools/chromium.js'

const { values } = parseArgs({
  options: {
    seconds: { type: 'string', default: '10' },
    delivery: { type: 'string', default: 'seeds,snapshots' },
    balls: { type: 'string', default: '30,100' },
    throttle: { type: 'string', default: '4' },
    board: { type: 'string', default: 'worker' },
    simulation: { type: 'string' }
  }
})
const SECONDS = Number(values.seconds)
const DELIVERIES = values.delivery.split(',')
const BALLS = values.balls.split(',').map(Number)
const THROTTLE = Number(values.throttle)
const BOARD = values.board
// A seeds room is simulated where the board is drawn by default: the worker, or the main thread with --board main.
const SIMULATIONS = (values.simulation ?? (BOARD === 'main' ? 'main' : 'worker')).split(',')
if (BOARD === 'main' && SIMULATIONS.includes('worker')) throw new Error('--simulation worker needs the board drawn in the worker (--board worker)')
for (const where of SIMULATIONS) if (where !== 'main' && where !== 'worker') throw new Error(`--simulation takes main and worker, not ${where}`)
const ROOM = '16-medium'
const BOTS = 8
const SIZES = [
  { name: '1366×800', options: { viewport: { width: 1366, height: 800 } } },
  { name: '390×844 DPR 2', options: { viewport: { width: 390, height: 844 }, deviceScaleFactor: 2, isMobile: true, hasTouch: true } }
]

const flightSeconds = meanFlightSeconds()
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-frame-cost-'))
const server = startServerProcess(`sqlite:${path.join(dir, 'ledger.sqlite')}`, { ...LIFTED_LIMITS, DROP_RATE: '100', STARTING_BALANCE: '100000000' })
const browser = await chromium.launch({ executablePath: CHROMIUM_PATH, headless: true, args: [...CHROMIUM_ARGS] })
const rows = []
try {
  const port = await server.port
  const base = `http://127.0.0.1:${port}`
  const bots = await Promise.all(Array.from({ length: BOTS }, () => openBot(base)))
  for (const delivery of DELIVERIES) {
    for (const size of SIZES) {
      for (const balls of BALLS) {
        // The simulation's place only matters where the page simulates: seeds.
        for (const simulation of delivery === 'seeds' ? SIMULATIONS : ['main']) {
          rows.push({ delivery, simulation, size: size.name, target: balls, ...await measure(base, bots, delivery, size, balls, simulation) })
        }
      }
    }
  }
  for (const bot of bots) bot.socket.close()
} finally {
  await browser.close()
  server.child.kill('SIGTERM')
  await server.exited
  fs.rmSync(dir, { recursive: true, force: true })
}

console.log(`player page, headless Chromium, CPU throttled ${THROTTLE}×, room ${ROOM}, board drawn in ${BOARD === 'main' ? 'the main thread' : 'a worker'}, ${SECONDS} s steady window each; mean flight ${flightSeconds.toFixed(2)} s`)
console.log('delivery   simulated  viewport        balls (target, drawn)  main thread ms/frame  of it JS  of it simulation  fps    frames')
for (const r of rows) {
  console.log(`${r.delivery.padEnd(9)}  ${(r.delivery === 'seeds' ? r.simulation : '–').padEnd(9)}  ${r.size.padEnd(14)}  ${String(r.target).padStart(6)}, ${r.drawn.toFixed(1).padStart(6)}         ${r.msPerFrame.toFixed(2).padStart(8)}         ${r.scriptMsPerFrame.toFixed(2).padStart(6)}    ${r.simMsPerFrame === null ? '     –' : r.simMsPerFrame.toFixed(2).padStart(6)}            ${r.fps.toFixed(1).padStart(5)}  ${String(r.frames).padStart(6)}`)
}

/** Mean ticks from release to landing on the room's board, in seconds (60 ticks a second). */
function meanFlightSeconds () {
  const [rows, risk] = ROOM.split('-')
  const board = createBoard({ rows: Number(rows), risk })
  let ticks = 0
  const n = 200
  for (let i = 0; i < n; i++) ticks += simulateDrop(board, (i * 2654435761 >>> 0).toString(16).padStart(8, '0').repeat(8)).ticks
  return ticks / n / 60
}

/** A bot player in the room: a guest session and a seeds socket (it reads nothing the page needs). */
async function openBot (base) {
  const response = await fetch(`${base}/api/session`, { method: 'POST' })
  const { token } = await response.json()
  const socket = new WebSocket(`${base.replace('http', 'ws')}/ws?token=${token}`)
  socket.binaryType = 'arraybuffer'
  await new Promise((resolve, reject) => {
    socket.addEventListener('message', function onWelcome (event) {
      if (typeof event.data !== 'string' || !event.data.startsWith('{"type":"welcome"')) return
      socket.removeEventListener('message', onWelcome)
      socket.send(JSON.stringify({ type: 'join', room: ROOM, delivery: 'seeds' }))
      resolve()
    })
    socket.addEventListener('error', () => reject(new Error('bot socket failed')))
  })
  return { socket }
}

/** Bots drop `perSecond` balls a second between them until stop() is called. */
function dropAtRate (bots, perSecond) {
  let sent = 0
  const started = performance.now()
  const timer = setInterval(() => {
    const due = Math.floor((performance.now() - started) / 1000 * perSecond)
    while (sent < due) bots[sent++ % bots.length].socket.send('{"type":"drop","bet":1}')
  }, 10)
  return { stop: () => clearInterval(timer) }
}

async function measure (base, bots, delivery, size, balls, simulation) {
  const context = await browser.newContext(size.options)
  const page = await context.newPage()
  await page.goto(`${base}/?delivery=${delivery}${BOARD === 'main' ? '&board=main' : ''}&simulation=${simulation}`)
  await page.waitForFunction(() => window.__plinko?.ready === true, null, { timeout: 60_000 })
  const drawnIn = await page.evaluate(() => window.__plinko.boardDrawnIn)
  if (drawnIn !== BOARD) throw new Error(`the board is drawn in ${drawnIn}, not ${BOARD}`)
  if (delivery === 'seeds') {
    const simulatedIn = await page.waitForFunction(() => window.__plinko.simulatedIn, null, { timeout: 30_000 }).then((handle) => handle.jsonValue())
    if (simulatedIn !== simulation) throw new Error(`the room is simulated in ${simulatedIn}, not ${simulation}`)
  }
  const cdp = await context.newCDPSession(page)
  await cdp.send('Performance.enable')
  await cdp.send('Emulation.setCPUThrottlingRate', { rate: THROTTLE })
  const rate = dropAtRate(bots, balls / flightSeconds)
  try {
    // Until the room is full: one flight and a bit.
    await new Promise((resolve) => setTimeout(resolve, (flightSeconds + 2) * 1000))
    const before = await sample(page, cdp)
    const drawn = []
    const end = Date.now() + SECONDS * 1000
    while (Date.now() < end) {
      await new Promise((resolve) => setTimeout(resolve, 250))
      drawn.push(await page.evaluate(() => window.__plinko.lastFrame.balls))
    }
    const after = await sample(page, cdp)
    const frames = after.frames - before.frames
    return {
      frames,
      drawn: drawn.reduce((a, b) => a + b, 0) / drawn.length,
      msPerFrame: (after.taskSeconds - before.taskSeconds) * 1000 / frames,
      scriptMsPerFrame: (after.scriptSeconds - before.scriptSeconds) * 1000 / frames,
      simMsPerFrame: after.simFrames > before.simFrames ? (after.simMs - before.simMs) / (after.simFrames - before.simFrames) : null,
      fps: frames / ((after.at - before.at) / 1000)
    }
  } finally {
    rate.stop()
    await context.close()
    // Let the room empty before the next run.
    await new Promise((resolve) => setTimeout(resolve, (flightSeconds + 1) * 1000))
  }
}

async function sample (page, cdp) {
  const { metrics } = await cdp.send('Performance.getMetrics')
  const { frames, seeds } = await page.evaluate(() => ({ frames: window.__plinko.frames, seeds: window.__plinko.seeds.room }))
  const metric = (name) => metrics.find((m) => m.name === name).value
  return { at: performance.now(), frames, taskSeconds: metric('TaskDuration'), scriptSeconds: metric('ScriptDuration'), simFrames: seeds?.frames ?? 0, simMs: seeds?.frameMs ?? 0 }
}
