import { spawn } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { eventually } from './eventually.js'
import { freePortRun } from './free-port.js'
import { LIFTED_LIMITS } from './lifted-limits.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')
const START_TIMEOUT_MS = 60_000

/**
 * `npm run cluster -- --workers N` (scripts/cluster.js) in a child process
 * of its own process group, its proxy on a free loopback port (worker i on
 * the port + 1 + i), for the load-test scripts: `LOG_LEVEL=warn` and every
 * per-address limit lifted (all players come from 127.0.0.1), `env` on top
 * (DATABASE_URL at least). Resolves once every worker answers
 * /n/{i}/api/health through the proxy; throws if the cluster exits first.
 * @param {{ workers: number, env: Record<string, string>, stdio?: import('node:child_process').StdioOptions }} options
 */
export async function startClusterProcess ({ workers, env, stdio = ['ignore', 'inherit', 'inherit'] }) {
  const port = await freePortRun(workers + 1)
  const child = spawn(process.execPath, [path.join(ROOT, 'scripts/cluster.js'), '--workers', String(workers), '--port', String(port)], {
    cwd: ROOT,
    detached: true,
    stdio,
    env: { ...process.env, LOG_LEVEL: 'warn', ...LIFTED_LIMITS, ...env }
  })
  const exited = new Promise((resolve) => child.once('exit', () => resolve(true)))
  const url = `http://127.0.0.1:${port}`
  const cluster = {
    child,
    url,
    /** Each worker's URL through the proxy (its PUBLIC_URL). */
    processes: Array.from({ length: workers }, (_, i) => `${url}/n/${i}`),
    /** SIGKILL to the whole group (proxy and workers). */
    kill () {
      try { process.kill(-child.pid, 'SIGKILL') } catch {}
    },
    /**
     * SIGTERM (graceful: balls settle, leases go back); past `timeoutMs`, SIGKILL to the group.
     * @returns {Promise<boolean>} it stopped by itself in time
     */
    async stop (timeoutMs = 30_000) {
      if (child.exitCode !== null || child.signalCode !== null) return true
      child.kill('SIGTERM')
      let timer
      const graceful = await Promise.race([exited, new Promise((resolve) => { timer = setTimeout(() => resolve(false), timeoutMs) })])
      clearTimeout(timer)
      if (!graceful) {
        cluster.kill()
        await exited
      }
      return graceful
    }
  }
  try {
    for (const worker of cluster.processes) {
      await eventually(async () => {
        if (child.exitCode !== null || child.signalCode !== null) throw new Error(`npm run cluster exited (${child.exitCode ?? child.signalCode}) during start-up`)
        return (await fetch(`${worker}/api/health`).catch(() => null))?.ok
      }, { timeoutMs: START_TIMEOUT_MS, intervalMs: 100 })
    }
  } catch (error) {
    cluster.kill()
    throw error
  }
  return cluster
}
