import { spawn } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')

/**
 * `node server/server.js` in a child process, as in production, on a free
 * loopback port over `databaseUrl`, with `env` on top. `port` resolves once
 * it logs that it listens; `exited` with { code, signal }; `output()` is what
 * it printed (the last 100 KB once it passes 1 MB). `root` runs another
 * checkout's server (an older version's, to record what it leaves behind).
 * @param {string} databaseUrl @param {Record<string, string>} [env]
 * @param {{ root?: string }} [options]
 */
export function startServerProcess (databaseUrl, env = {}, { root = ROOT } = {}) {
  const child = spawn(process.execPath, [path.join(root, 'server/server.js')], {
    cwd: root,
    env: {
      ...process.env,
      DATABASE_URL: databaseUrl,
      PORT: '0',
      HOST: '127.0.0.1',
      LOG_LEVEL: 'info',
      ...env
    },
    stdio: ['ignore', 'pipe', 'pipe']
  })
  let output = ''
  const exited = new Promise((resolve) => child.once('exit', (code, signal) => resolve({ code, signal })))
  const port = new Promise((resolve, reject) => {
    const onData = (chunk) => {
      output += chunk
      if (output.length > 1e6) output = output.slice(-1e5)
      const match = /listening at http:\/\/127\.0\.0\.1:(\d+)/.exec(output)
      if (match) resolve(Number(match[1]))
    }
    child.stdout.on('data', onData)
    child.stderr.on('data', onData)
    exited.then(() => reject(new Error(`server exited before listening:\n${output}`)))
  })
  return { child, port, exited, output: () => output }
}
