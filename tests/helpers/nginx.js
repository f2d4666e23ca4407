import { spawn, spawnSync } from 'node:child_process'
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { freePort } from '../../tools/free-port.js'
import { eventually } from '../../tools/eventually.js'

const CONF = fileURLToPath(new URL('../../deploy/nginx.conf', import.meta.url))

/**
 * Debian's nginx (`apt-get install nginx`, which .ci/run does) running the
 * repository's own deploy/nginx.conf, with the compose file's replicas
 * (server1:8080, server2:8080) replaced by loopback ports and its port by a
 * free one. Fails, never skips, when nginx is missing.
 * @param {{ server1: number, server2: number }} upstreams ports of the two replicas
 */
export async function startNginx ({ server1, server2 }) {
  if (spawnSync('nginx', ['-v']).error) throw new Error('nginx not found: apt-get install nginx (the proxy tests run the real deploy/nginx.conf)')
  const port = await freePort()
  const dir = mkdtempSync(join(tmpdir(), 'plinko-nginx-'))
  const conf = readFileSync(CONF, 'utf8')
    .replaceAll('server1:8080', `127.0.0.1:${server1}`)
    .replaceAll('server2:8080', `127.0.0.1:${server2}`)
    .replace('listen 8080;', `listen 127.0.0.1:${port};`)
    .replace('worker_processes auto;', 'worker_processes 1;')
    .replace('worker_connections 16384;', 'worker_connections 1024;')
  writeFileSync(join(dir, 'nginx.conf'), `pid ${join(dir, 'nginx.pid')};\nerror_log ${join(dir, 'error.log')} warn;\n${conf.replace('http {', `http {\n  access_log off;\n  client_body_temp_path ${dir}/body;\n  proxy_temp_path ${dir}/proxy;\n`)}`)
  const child = spawn('nginx', ['-p', dir, '-c', join(dir, 'nginx.conf'), '-g', 'daemon off;'], { stdio: ['ignore', 'pipe', 'pipe'] })
  let output = ''
  child.stdout.on('data', (chunk) => { output += chunk })
  child.stderr.on('data', (chunk) => { output += chunk })
  const exited = new Promise((resolve) => child.once('exit', resolve))
  await eventually(async () => {
    if (child.exitCode !== null) throw new Error(`nginx exited: ${output}`)
    return (await fetch(`http://127.0.0.1:${port}/n/server1/api/health`).catch(() => null))?.ok
  }, { timeoutMs: 15_000, intervalMs: 50 })
  return {
    port,
    async stop () {
      child.kill('SIGTERM')
      await exited
      rmSync(dir, { recursive: true, force: true })
    }
  }
}
