import { spawn } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { OPERATOR_TOKEN } from '../../server/helpers/server.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../..')

/**
 * `node server/server.js` in a child process, as in production, on a free
 * port. Resolves `port` once it listens; `exited` with { code, signal }.
 * @param {string} databaseUrl @param {Record<string, string>} [env]
 */
export function startServerProcess (databaseUrl, env = {}) {
  const child = spawn(process.execPath, [path.join(ROOT, 'server/server.js')], {
    cwd: ROOT,
    env: {
      ...process.env,
      DATABASE_URL: databaseUrl,
      PORT: '0',
      HOST: '127.0.0.1',
      LOG_LEVEL: 'info',
      OPERATOR_TOKEN,
      CLIENT_DIR: '/nonexistent/plinko-client',
      HTTP_RATE_LIMIT: '1000000',
      SESSION_RATE_LIMIT: '1000000',
      ...env
    },
    stdio: ['ignore', 'pipe', 'pipe']
  })
  let output = ''
  const exited = new Promise((resolve) => child.once('exit', (code, signal) => resolve({ code, signal })))
  const port = new Promise((resolve, reject) => {
    const onData = (chunk) => {
      output += chunk
      const match = /listening at http:\/\/127\.0\.0\.1:(\d+)/.exec(output)
      if (match) resolve(Number(match[1]))
    }
    child.stdout.on('data', onData)
    child.stderr.on('data', onData)
    exited.then(() => reject(new Error(`server exited before listening:\n${output}`)))
  })
  return { child, port, exited, output: () => output }
}
