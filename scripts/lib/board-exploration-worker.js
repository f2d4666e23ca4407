import { parentPort, workerData } from 'node:worker_threads'
import { buildBoard } from '../../engine/board.js'
import { simulateDrop } from '../../engine/drop-simulator.js'
import { dropSeedSync } from '../../cli/drop-seeds.js'

// Simulates nonces [from, to) of a candidate board; replies with bucket counts and each drop's ticks.
const { rules, rows, seed, from, to } = workerData
const board = buildBoard(rules, rows, 'medium')
const counts = new Array(rows + 1).fill(0)
const ticks = new Uint32Array(to - from)
for (let nonce = from; nonce < to; nonce++) {
  const outcome = simulateDrop(board, dropSeedSync(seed, 'explore', nonce))
  counts[outcome.bucket]++
  ticks[nonce - from] = outcome.ticks
}
parentPort.postMessage({ counts, ticks })
