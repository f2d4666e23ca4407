#!/usr/bin/env node
/**
 * What one socket write costs this machine's kernel, with no game around it:
 * `node bench/loopback-writes.js [--sockets 6000] [--bytes 500] [--per-tick 450] [--ticks 150] [--rounds 2] [--steer]`
 * (run by hand; issue #23's "the profile of what stops it").
 *
 * `--sockets` loopback TCP connections (Nagle off, as ws sets them) to a
 * reader in a child process that reads and discards; this process on CPU 0
 * and the reader on CPU 1 when taskset can pin them. Each connection is
 * written a `--bytes` buffer, two ways, interleaved round by round:
 *
 * - **as the server writes**: `--per-tick` frames a tick (6,000 seeds
 *   players get 4.5 frames a second each: 450 a tick), the sockets in turn,
 *   FLUSH_CHUNK of them per turn of the event loop
 *   (server/realtime/write-batcher.js), a tick every 16 ms; the reader
 *   is mostly idle between them, so most writes wake it;
 * - **back to back**: every socket once per round, FLUSH_CHUNK per turn,
 *   no pause; the reader stays busy.
 *
 * Printed: this process's user and system CPU µs per frame
 * (process.cpuUsage: one thread writes, nothing else runs here). With
 * `--steer` (Linux and root) each way is measured again with the
 * loopback's receive processing steered to CPU 1
 * (loadtest/driver/loopback-steering.js, as `npm run loadtest:capacity --
 * --steer-loopback` does; restored after): the receiver's half of each
 * write leaves this core, and an inter-processor interrupt per write
 * takes its place. Exit code 0 whatever the figures; 2 for a bad argument.
 */
import net from 'node:net'
import { fork, spawnSync } from 'node:child_process'
import { fileURLToPath } from 'node:url'
import { parseArgs } from 'node:util'
import { setImmediate as nextTurn, setTimeout as sleep } from 'node:timers/promises'
import { FLUSH_CHUNK } from '../server/realtime/write-batcher.js'
import { canPin, pinSelf } from '../loadtest/lean/measure-server.js'
import { steerLoopbackReceiveUntilExit } from '../loadtest/driver/loopback-steering.js'

const USAGE = 'usage: node bench/loopback-writes.js [--sockets N] [--bytes N] [--per-tick N] [--ticks N] [--rounds N] [--steer]'
const TICK_MS = 16

/** The child: accepts connections and discards what they send; tells its parent the port. */
function runReader () {
  const server = net.createServer((socket) => socket.on('data', () => {}))
  server.listen(0, '127.0.0.1', () => process.send(server.address().port))
  process.on('disconnect', () => process.exit(0))
}

async function main () {
  let values
  try {
    values = parseArgs({
      options: {
        sockets: { type: 'string', default: '6000' },
        bytes: { type: 'string', default: '500' },
        'per-tick': { type: 'string', default: '450' },
        ticks: { type: 'string', default: '150' },
        rounds: { type: 'string', default: '2' },
        steer: { type: 'boolean', default: false },
        help: { type: 'boolean', short: 'h' }
      }
    }).values
  } catch (error) {
    console.error(`${error.message}\n${USAGE}`)
    process.exit(2)
  }
  if (values.help) return console.log(USAGE)
  const [sockets, bytes, perTick, ticks, rounds] = ['sockets', 'bytes', 'per-tick', 'ticks', 'rounds'].map((name) => Number(values[name]))
  if (![sockets, bytes, perTick, ticks, rounds].every((n) => Number.isInteger(n) && n > 0)) {
    console.error(USAGE)
    process.exit(2)
  }
  const pinned = canPin() && pinSelf('0')
  const reader = fork(fileURLToPath(import.meta.url), ['--reader'], { stdio: ['ignore', 'inherit', 'inherit', 'ipc'] })
  process.once('exit', () => reader.kill())
  try {
    if (pinned) spawnSync('taskset', ['-a', '-p', '-c', '1', String(reader.pid)], { stdio: 'ignore' })
    const port = await new Promise((resolve, reject) => { reader.once('message', resolve); reader.once('exit', () => reject(new Error('the reader exited'))) })
    const connections = await connectAll(port, sockets)
    const frame = Buffer.alloc(bytes, 0x5a)
    console.log(`loopback writes: ${sockets} sockets, ${bytes}-byte frames, ${FLUSH_CHUNK} a turn; ${pinned ? 'writer on CPU 0, reader on CPU 1' : 'NOT pinned (no taskset or one CPU)'}`)
    const settings = values.steer ? ['not steered', 'steered to CPU 1'] : ['not steered']
    // Each socket about as often back to back as in the ticks.
    const times = Math.max(1, Math.round(perTick * ticks / sockets))
    for (let round = 1; round <= rounds; round++) {
      for (const setting of settings) {
        const restore = setting === 'not steered' ? () => {} : steerForNow()
        try {
          const ticked = await measure(() => writeTicks(connections, frame, perTick, ticks), perTick * ticks)
          const burst = await measure(() => writeBackToBack(connections, frame, times), sockets * times)
          console.log(`round ${round}, ${setting}: as the server writes (${perTick} a tick) ${ticked}; back to back ${burst}`)
        } finally {
          restore()
        }
      }
    }
    for (const socket of connections) socket.destroy()
  } finally {
    reader.kill()
  }
}

/**
 * Steers the loopback's receive to CPU 1 until the returned function is
 * called (or the process ends: steerLoopbackReceiveUntilExit); exits with
 * code 1 and the reason when it cannot (not Linux, not root).
 */
function steerForNow () {
  try {
    return steerLoopbackReceiveUntilExit(1)
  } catch (error) {
    console.error(error.message)
    process.exit(1)
  }
}

/** Opens `count` connections to the reader, 500 at a time (the listen backlog). */
async function connectAll (port, count) {
  const connections = []
  while (connections.length < count) {
    const batch = Math.min(500, count - connections.length)
    connections.push(...await Promise.all(Array.from({ length: batch }, () => new Promise((resolve, reject) => {
      const socket = net.connect(port, '127.0.0.1', () => resolve(socket))
      socket.setNoDelay(true)
      socket.once('error', reject)
    }))))
  }
  return connections
}

/** This process's CPU over `work`, per frame: "user U, system S µs a frame". */
async function measure (work, frames) {
  const before = process.cpuUsage()
  await work()
  const used = process.cpuUsage(before)
  return `user ${(used.user / frames).toFixed(2)}, system ${(used.system / frames).toFixed(2)} µs a frame`
}

/** The next socket writeTicks writes. */
let next = 0

/** `perTick` frames a tick for `ticks` ticks, the sockets in turn, FLUSH_CHUNK a turn. */
async function writeTicks (connections, frame, perTick, ticks) {
  for (let tick = 0; tick < ticks; tick++) {
    for (let left = perTick; left > 0; left -= FLUSH_CHUNK) {
      for (let i = Math.min(FLUSH_CHUNK, left); i > 0; i--) connections[next++ % connections.length].write(frame)
      await nextTurn()
    }
    await sleep(TICK_MS)
  }
}

/** Every socket `times` times, FLUSH_CHUNK a turn, no pause. */
async function writeBackToBack (connections, frame, times) {
  for (let time = 0; time < times; time++) {
    for (let start = 0; start < connections.length; start += FLUSH_CHUNK) {
      const end = Math.min(connections.length, start + FLUSH_CHUNK)
      for (let i = start; i < end; i++) connections[i].write(frame)
      await nextTurn()
    }
  }
}

if (process.argv[2] === '--reader') runReader()
else await main()
