import fs from 'node:fs'

/**
 * What the scheduler says of each thread of a process: its name and, since
 * the thread started, the seconds it ran on a CPU and the seconds it was
 * runnable but waited for one (/proc/PID/task/TID/schedstat, in ns).
 * Null without /proc or once the process is gone.
 * @param {number} pid
 * @returns {Map<number, { name: string, runS: number, waitS: number }> | null}
 */
export function readThreadSchedules (pid) {
  let tids
  try {
    tids = fs.readdirSync(`/proc/${pid}/task`)
  } catch {
    return null
  }
  const threads = new Map()
  for (const tid of tids) {
    try {
      const [run, wait] = fs.readFileSync(`/proc/${pid}/task/${tid}/schedstat`, 'utf8').split(' ').map(Number)
      const name = fs.readFileSync(`/proc/${pid}/task/${tid}/comm`, 'utf8').trim()
      threads.set(Number(tid), { name, runS: run / 1e9, waitS: wait / 1e9 })
    } catch {
      // The thread ended between the listing and the read.
    }
  }
  return threads
}

/**
 * The thread named `name` that ran the most between two readings, with the
 * shares of the window it ran and waited for a CPU; null if none ran. A
 * thread started in between counts from zero. Node names every worker
 * thread "WorkerThread"; under load the server's busiest is the SQLite
 * writer (the reader serves listings, the checkpointer wakes once a second).
 * @param {ReturnType<typeof readThreadSchedules>} from
 * @param {ReturnType<typeof readThreadSchedules>} to
 * @param {string} name
 * @param {number} seconds the window's length
 * @returns {{ tid: number, runShare: number, waitShare: number } | null}
 */
export function busiestThread (from, to, name, seconds) {
  if (!from || !to || !(seconds > 0)) return null
  let busiest = null
  for (const [tid, now] of to) {
    if (now.name !== name) continue
    const before = from.get(tid) ?? { runS: 0, waitS: 0 }
    const runS = now.runS - before.runS
    if (runS > 0 && (busiest === null || runS > busiest.runS)) busiest = { tid, runS, waitS: now.waitS - before.waitS }
  }
  return busiest && { tid: busiest.tid, runShare: busiest.runS / seconds, waitShare: busiest.waitS / seconds }
}
