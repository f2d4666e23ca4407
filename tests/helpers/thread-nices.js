import fs from 'node:fs'

/**
 * The nice value of every thread of this process, by thread id (Linux
 * /proc). A thread that ends between the listing and its read is left
 * out: the test runner's and other files' threads come and go.
 * @returns {Map<number, number>}
 */
export function threadNices () {
  const nices = new Map()
  for (const tid of fs.readdirSync('/proc/self/task')) {
    let stat
    try {
      stat = fs.readFileSync(`/proc/self/task/${tid}/stat`, 'utf8')
    } catch {
      continue
    }
    nices.set(Number(tid), Number(stat.slice(stat.lastIndexOf(')') + 2).split(' ')[16]))
  }
  return nices
}
