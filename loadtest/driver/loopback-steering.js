import fs from 'node:fs'
import path from 'node:path'

/**
 * Where the loopback's receive processing runs, for a capacity run that
 * wants the server's core to pay only for the server.
 *
 * Over loopback, the kernel delivers a TCP segment to the receiving socket
 * inside the sender's own system call (the receiver's softirq half runs on
 * the sender's CPU). So every frame the server writes to the load
 * generator's sockets also costs the server's core the generator's receive:
 * about 3–4 µs a frame on this VM, some ten points of a core at 6,000
 * players (loadtest/RESULTS.md). Players' machines pay that on a real
 * network. Receive Packet Steering (RPS) on `lo` moves that half to another
 * CPU: every loopback packet's receive processing, in both directions (RPS
 * hashes a flow the same either way), then runs on the generator's CPU,
 * the server's own receive of the players' messages included (a few points
 * of a core: the figures are then a little kind to the server, and say so).
 *
 * Linux only, and root: the setting is the files
 * /sys/class/net/lo/queues/rx-N/rps_cpus (a hexadecimal CPU mask, 0 = off).
 */
export const LOOPBACK_QUEUES = '/sys/class/net/lo/queues'

export class LoopbackSteeringError extends Error {
  constructor (message) {
    super(message)
    this.name = 'LoopbackSteeringError'
    this.code = 'E_LOOPBACK_STEERING'
  }
}

/**
 * A CPU mask as the kernel's rps_cpus takes it: hexadecimal, in groups of
 * eight digits separated by commas, the lowest CPUs last.
 * @param {number} cpu
 */
export function cpuMask (cpu) {
  if (!Number.isInteger(cpu) || cpu < 0 || cpu > 4095) throw new RangeError(`no CPU ${cpu}`)
  const hex = (1n << BigInt(cpu)).toString(16)
  const groups = []
  for (let end = hex.length; end > 0; end -= 8) groups.unshift(hex.slice(Math.max(0, end - 8), end))
  return groups.join(',')
}

/**
 * Steers the receive processing of every loopback queue to `cpu`; returns a
 * function that puts back what each queue had (call it once the run is
 * over, whatever happened). Throws a LoopbackSteeringError, changing
 * nothing, when it cannot (not Linux, not root).
 * @param {number} cpu
 * @param {{ queues?: string }} [options] queues: the directory of lo's queues (tests use a stand-in)
 * @returns {() => void}
 */
export function steerLoopbackReceive (cpu, { queues = LOOPBACK_QUEUES } = {}) {
  const mask = cpuMask(cpu)
  /** @type {[string, string][]} each file and what it held */
  const saved = []
  const restore = () => {
    for (const [file, before] of saved.splice(0).reverse()) {
      try { fs.writeFileSync(file, before) } catch {} // best effort: nothing else to do with an error here
    }
  }
  try {
    const names = fs.readdirSync(queues).filter((name) => /^rx-\d+$/.test(name)).sort()
    if (names.length === 0) throw new Error(`no rx-N queue in ${queues}`)
    for (const name of names) {
      const file = path.join(queues, name, 'rps_cpus')
      const before = fs.readFileSync(file, 'utf8').trim()
      fs.writeFileSync(file, mask)
      saved.push([file, before])
    }
  } catch (error) {
    restore()
    throw new LoopbackSteeringError(`cannot steer the loopback's receive processing to CPU ${cpu} (${error.code ?? error.message}): it needs Linux and root, to write ${queues}/rx-N/rps_cpus`)
  }
  return restore
}

/** Signals that end a steering process through 'exit' (steerLoopbackReceiveUntilExit). */
const ENDING_SIGNALS = Object.freeze(['SIGINT', 'SIGTERM'])

/**
 * steerLoopbackReceive, put back on any way out: when the returned
 * function is called, when the process exits, and on SIGINT or SIGTERM
 * (which then end the process with code 130, through 'exit'). The
 * steering outlives the process otherwise. The returned function also
 * takes those listeners off again. Throws as steerLoopbackReceive does,
 * changing nothing.
 * @param {number} cpu
 * @param {{ queues?: string }} [options] as steerLoopbackReceive's
 * @returns {() => void}
 */
export function steerLoopbackReceiveUntilExit (cpu, options) {
  const restore = steerLoopbackReceive(cpu, options)
  const endThroughExit = () => process.exit(130)
  process.once('exit', restore)
  for (const signal of ENDING_SIGNALS) process.once(signal, endThroughExit)
  return () => {
    process.off('exit', restore)
    for (const signal of ENDING_SIGNALS) process.off(signal, endThroughExit)
    restore()
  }
}
