import fs from 'node:fs'
import os from 'node:os'

/**
 * Lowers the scheduling priority of the calling thread only. On Linux a
 * thread has its own nice value, and setpriority(2) given a thread's id
 * (its entry under /proc/thread-self) changes that thread alone: the event
 * loop keeps its priority. Best effort: elsewhere, or when the system
 * refuses, nothing changes and false is returned.
 * @param {number} nice 1 (a little below normal) … 19 (only when nothing else runs)
 * @returns {boolean} the thread now runs at `nice`
 */
export function lowerThisThreadPriority (nice) {
  let tid
  try {
    tid = Number(fs.readlinkSync('/proc/thread-self').split('/').pop())
  } catch {
    return false
  }
  if (!Number.isInteger(tid) || tid <= 0) return false
  try {
    os.setPriority(tid, nice)
    return os.getPriority(tid) === nice
  } catch {
    return false
  }
}
