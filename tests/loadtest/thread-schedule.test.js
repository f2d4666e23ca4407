import { describe, it, expect } from 'vitest'
import { Worker } from 'node:worker_threads'
import { once } from 'node:events'
import { readThreadSchedules, busiestThread } from '../../loadtest/driver/thread-schedule.js'

describe("a process's threads as the scheduler counts them", () => {
  it('finds a busy worker thread and the share of the window it ran', async () => {
    const from = readThreadSchedules(process.pid)
    expect(from.get(process.pid)).toMatchObject({ name: expect.any(String) })
    const started = performance.now()
    // Busy for 300 ms of its own, then it says so and waits to be ended:
    // a worker that ended by itself could leave /proc before the reading.
    const worker = new Worker('const { parentPort } = require("node:worker_threads"); const end = Date.now() + 300; while (Date.now() < end); parentPort.postMessage("done"); parentPort.on("message", () => {})', { eval: true })
    await once(worker, 'message')
    const to = readThreadSchedules(process.pid)
    const seconds = (performance.now() - started) / 1000
    await worker.terminate()
    const busy = busiestThread(from, to, 'WorkerThread', seconds)
    expect(busy).not.toBeNull()
    expect(to.get(busy.tid).runS).toBeGreaterThanOrEqual(0.25)
    expect(busy.runShare).toBeGreaterThan(0.25 / seconds - 0.01)
    expect(busy.waitShare).toBeGreaterThanOrEqual(0)
    expect(busy.runShare + busy.waitShare).toBeLessThanOrEqual(1.01)
  })

  it('picks the thread of that name that ran most in the window, counting one started in it from zero', () => {
    const from = new Map([[1, { name: 'node-MainThread', runS: 5, waitS: 1 }], [2, { name: 'WorkerThread', runS: 9, waitS: 1 }], [3, { name: 'WorkerThread', runS: 1, waitS: 0 }]])
    const to = new Map([[1, { name: 'node-MainThread', runS: 12, waitS: 2 }], [2, { name: 'WorkerThread', runS: 9.5, waitS: 1 }], [3, { name: 'WorkerThread', runS: 3, waitS: 4 }], [4, { name: 'WorkerThread', runS: 1.5, waitS: 0.2 }]])
    expect(busiestThread(from, to, 'WorkerThread', 10)).toEqual({ tid: 3, runShare: 0.2, waitShare: 0.4 })
    expect(busiestThread(from, new Map([[4, { name: 'WorkerThread', runS: 2.5, waitS: 0.5 }]]), 'WorkerThread', 10)).toEqual({ tid: 4, runShare: 0.25, waitShare: 0.05 })
    expect(busiestThread(from, to, 'libuv-worker', 10)).toBeNull()
    expect(busiestThread(null, to, 'WorkerThread', 10)).toBeNull()
    expect(readThreadSchedules(2 ** 30)).toBeNull()
  })
})
