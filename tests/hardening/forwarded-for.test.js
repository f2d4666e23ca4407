import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { mkdtempSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import WebSocket from 'ws'
import { startServerProcess } from '../../tools/server-process.js'
import { freePort } from '../../tools/free-port.js'
import { createProxy } from '../../server/cluster/proxy.js'
import { startNginx } from '../helpers/nginx.js'

/**
 * A spoofed X-Forwarded-For through each front the project ships (issue #14,
 * item 3): the cluster proxy of `npm run cluster` and nginx with
 * deploy/nginx.conf. Each sends the server the peer it sees, whatever the
 * client wrote, and the server believes exactly that hop (TRUST_PROXY), so
 * per-address limits hold: three sessions a minute and two sockets per
 * address here, whatever addresses the client claims.
 */
const LIMITS = { SESSION_RATE_LIMIT: '3', WS_MAX_CONNECTIONS_PER_IP: '2', HTTP_RATE_LIMIT: '1000000', CLIENT_DIR: '/nonexistent/plinko-client' }
const SPOOFS = ['6.6.6.6', '6.6.6.6, 203.0.113.9', '203.0.113.10', '10.0.0.1, 10.0.0.2, 10.0.0.3', 'for=1.2.3.4']

const dir = mkdtempSync(join(tmpdir(), 'plinko-xff-'))
const processes = []
let proxy
let nginx
const fronts = {}

beforeAll(async () => {
  // Behind the cluster proxy (on loopback) and behind nginx (one hop): each server its own limits.
  const behindProxy = startServerProcess(`sqlite:${join(dir, 'proxy.sqlite')}`, { ...LIMITS, TRUST_PROXY: 'loopback' })
  const behindNginx = startServerProcess(`sqlite:${join(dir, 'nginx.sqlite')}`, { ...LIMITS, TRUST_PROXY: '1' })
  processes.push(behindProxy, behindNginx)
  const [proxyTarget, nginxTarget] = await Promise.all([behindProxy.port, behindNginx.port])
  proxy = createProxy({ targets: [{ host: '127.0.0.1', port: proxyTarget }], log: { warn () {} } })
  const proxyPort = await freePort()
  await new Promise((resolve) => proxy.listen(proxyPort, '127.0.0.1', resolve))
  nginx = await startNginx({ server1: nginxTarget, server2: nginxTarget })
  fronts['cluster proxy'] = `127.0.0.1:${proxyPort}`
  fronts.nginx = `127.0.0.1:${nginx.port}`
}, 60_000)

afterAll(async () => {
  await nginx?.stop()
  await new Promise((resolve) => (proxy ? proxy.close(resolve) : resolve()))
  for (const p of processes) { p.child.kill('SIGTERM'); await p.exited }
  rmSync(dir, { recursive: true, force: true })
})

/** Opens a socket claiming `xff`; resolves with 'welcome' or the refusal's code and close code. */
function socketClaiming (front, token, xff) {
  return new Promise((resolve) => {
    const socket = new WebSocket(`ws://${front}/ws?token=${token}`, { headers: { 'X-Forwarded-For': xff, Forwarded: 'for=9.9.9.9', 'X-Real-IP': '9.9.9.9' } })
    let refusal = null
    socket.on('message', (data) => {
      const message = JSON.parse(data.toString())
      if (message.type === 'welcome') resolve({ socket, outcome: 'welcome' })
      if (message.type === 'error') refusal = message.code
    })
    socket.on('close', (code) => resolve({ socket, outcome: `${refusal} ${code}` }))
    socket.on('error', () => {})
  })
}

describe.each(['cluster proxy', 'nginx'])('X-Forwarded-For through the %s', (name) => {
  it('cannot spoof its way past the per-address session limit', async () => {
    const front = fronts[name]
    const statuses = []
    const bodies = []
    for (const xff of SPOOFS) {
      const response = await fetch(`http://${front}/api/session`, { method: 'POST', headers: { 'X-Forwarded-For': xff, Forwarded: 'for=9.9.9.9', 'X-Real-IP': '9.9.9.9' } })
      statuses.push(response.status)
      bodies.push(await response.json())
    }
    // Three a minute from one address, whatever the header says.
    expect(statuses).toEqual([201, 201, 201, 429, 429])
    expect(bodies[3].code).toBe('E_RATE_LIMITED')
    fronts[`${name} token`] = bodies[0].token
  })

  it('cannot spoof its way past the per-address socket limit', async () => {
    const front = fronts[name]
    const token = fronts[`${name} token`]
    const results = []
    for (const xff of SPOOFS.slice(0, 3)) results.push(await socketClaiming(front, token, xff))
    expect(results.map((r) => r.outcome)).toEqual(['welcome', 'welcome', 'E_TOO_MANY_CONNECTIONS 4429'])
    for (const { socket } of results) socket.terminate()
  })
})
