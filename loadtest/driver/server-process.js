import fs from 'node:fs'
import path from 'node:path'
import { spawn } from 'node:child_process'
import { randomBytes } from 'node:crypto'
import { fileURLToPath } from 'node:url'
import { freePort } from '../../tools/free-port.js'
import { LIFTED_LIMITS } from '../../tools/lifted-limits.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..')
const SERVER_ENTRY = path.join(ROOT, 'server', 'server.js')
const READY_TIMEOUT_MS = 60_000
const STOP_TIMEOUT_MS = 60_000

export { freePort }

/**
 * Starts the game server (server/server.js) as a child process on
 * 127.0.0.1 with a fresh SQLite ledger in `dataDir`, load-test friendly
 * limits (the per-IP HTTP and session limits would refuse thousands of
 * players from one address) and `env` on top. Resolves once
 * GET /api/health answers.
 * @param {object} options
 * @param {string} options.dataDir fresh folder for the ledger
 * @param {string} options.logFile server stdout and stderr
 * @param {Record<string, string>} [options.env]
 * @param {string} [options.profileDir] run under node --cpu-prof, profile written here on exit
 * @param {string} [options.cpus] taskset CPU list, e.g. "0"
 */
export async function startServer ({ dataDir, logFile, env = {}, profileDir, cpus }) {
  fs.mkdirSync(dataDir, { recursive: true })
  const port = await freePort()
  const nodeArgs = [...(profileDir ? ['--cpu-prof', `--cpu-prof-dir=${profileDir}`] : []), SERVER_ENTRY]
  const [command, args] = cpus ? ['taskset', ['-c', cpus, process.execPath, ...nodeArgs]] : [process.execPath, nodeArgs]
  const serverEnv = {
    ...process.env,
    PORT: String(port),
    HOST: '127.0.0.1',
    DATABASE_URL: `sqlite:${path.join(dataDir, 'ledger.sqlite')}`,
    OPERATOR_TOKEN: randomBytes(24).toString('hex'),
    LOG_LEVEL: 'warn',
    // Every virtual user connects from 127.0.0.1.
    ...LIFTED_LIMITS,
    ...env
  }
  const log = fs.openSync(logFile, 'a')
  const child = spawn(command, args, { cwd: ROOT, env: serverEnv, stdio: ['ignore', log, log] })
  fs.closeSync(log)
  let exited = null
  const exit = new Promise((resolve) => child.once('exit', (code, signal) => { exited = { code, signal }; resolve(exited) }))
  const url = `http://127.0.0.1:${port}`

  const deadline = Date.now() + READY_TIMEOUT_MS
  for (;;) {
    if (exited) throw new Error(`server exited during start-up (${exited.code ?? exited.signal}); see ${logFile}:\n${tail(logFile)}`)
    try {
      const response = await fetch(`${url}/api/health`, { signal: AbortSignal.timeout(2000) })
      if (response.ok) break
    } catch {}
    if (Date.now() > deadline) {
      child.kill('SIGKILL')
      throw new Error(`server did not answer ${url}/api/health within ${READY_TIMEOUT_MS / 1000} s; see ${logFile}`)
    }
    await new Promise((resolve) => setTimeout(resolve, 100))
  }

  return {
    url,
    pid: child.pid,
    get exited () { return exited },
    /**
     * SIGTERM (the server settles what is in flight and closes its sockets),
     * then SIGKILL if it has not exited in time. Resolves with how it exited.
     */
    async stop () {
      if (exited) return exited
      child.kill('SIGTERM')
      const timer = setTimeout(() => child.kill('SIGKILL'), STOP_TIMEOUT_MS)
      const result = await exit
      clearTimeout(timer)
      return result
    }
  }
}

function tail (file, lines = 20) {
  try {
    return fs.readFileSync(file, 'utf8').trim().split('\n').slice(-lines).join('\n')
  } catch {
    return ''
  }
}
