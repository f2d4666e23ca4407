import { spawn } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { freePort } from './free-port.js'

/**
 * A throwaway redis-server on a free loopback port, without persistence, in
 * a temporary folder that stop() removes; killed if this process exits
 * first. REDIS_SERVER picks the binary (default: /usr/bin/redis-server if
 * present, else redis-server on PATH). Used by `npm run cluster` when no
 * REDIS_URL is given, and by the cluster tests.
 * @returns {Promise<{ url: string, stop: () => Promise<void> }>}
 */
export async function startRedis () {
  const port = await freePort()
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-redis-'))
  const binary = process.env.REDIS_SERVER ?? (fs.existsSync('/usr/bin/redis-server') ? '/usr/bin/redis-server' : 'redis-server')
  const child = spawn(binary, ['--port', String(port), '--bind', '127.0.0.1', '--save', '', '--appendonly', 'no', '--dir', dir], { stdio: ['ignore', 'pipe', 'pipe'] })
  const kill = () => { try { child.kill('SIGKILL') } catch {} }
  process.once('exit', kill)
  let output = ''
  try {
    await new Promise((resolve, reject) => {
      const onData = (chunk) => {
        output += chunk
        if (/Ready to accept connections/.test(output)) resolve()
      }
      child.stdout.on('data', onData)
      child.stderr.on('data', onData)
      child.once('error', (error) => reject(new Error(`cannot start ${binary} (install redis-server or set REDIS_URL): ${error.message}`)))
      child.once('exit', () => reject(new Error(`redis-server exited:\n${output}`)))
    })
  } catch (error) {
    process.removeListener('exit', kill)
    fs.rmSync(dir, { recursive: true, force: true })
    throw error
  }
  return {
    url: `redis://127.0.0.1:${port}`,
    async stop () {
      process.removeListener('exit', kill)
      if (child.exitCode === null && child.signalCode === null) {
        const exited = new Promise((resolve) => child.once('exit', resolve))
        child.kill('SIGTERM')
        await exited
      }
      fs.rmSync(dir, { recursive: true, force: true })
    }
  }
}
