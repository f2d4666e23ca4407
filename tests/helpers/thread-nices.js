import fs from 'node:fs'
import { readThreadStat } from '../../loadtest/driver/metrics-sampler.js'

/**
 * The nice value of every thread of this process, by thread id (Linux
 * /proc). A thread that ends between the listing and its read is left
 * out (readThreadStat gives null): the test runner's and other files'
 * threads come and go.
 * @returns {Map<number, number>}
 */
export function threadNices () {
  const nices = new Map()
  for (const tid of fs.readdirSync('/proc/self/task').map(Number)) {
    const stat = readThreadStat(process.pid, tid)
    if (stat !== null) nices.set(tid, stat.nice)
  }
  return nices
}
