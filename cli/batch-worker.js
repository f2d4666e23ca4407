import { parentPort, workerData } from 'node:worker_threads'
import { createBoard } from '../engine/board.js'
import { simulateDrop } from '../engine/drop-simulator.js'
import { dropSeedSync } from './drop-seeds.js'

// Simulates nonces [from, to) and reports bucket counts, with progress
// messages every `progressEvery` drops.
const { rows, engineVersion, serverSeed, clientSeed, from, to, progressEvery } = workerData
const board = createBoard({ rows, risk: 'medium', engineVersion })
const counts = new Array(rows + 1).fill(0)
let ticks = 0
let maxTicks = 0
let done = 0
for (let nonce = from; nonce < to; nonce++) {
  const outcome = simulateDrop(board, dropSeedSync(serverSeed, clientSeed, nonce))
  counts[outcome.bucket]++
  ticks += outcome.ticks
  if (outcome.ticks > maxTicks) maxTicks = outcome.ticks
  if (++done % progressEvery === 0) parentPort.postMessage({ type: 'progress', done: progressEvery })
}
parentPort.postMessage({ type: 'progress', done: done % progressEvery })
parentPort.postMessage({ type: 'result', counts, ticks, maxTicks })
