import { describe, it, expect, afterEach } from 'vitest'
import { fork } from 'node:child_process'
import { once } from 'node:events'
import { fileURLToPath } from 'node:url'
import WebSocket from 'ws'
import { createProxy } from '../../server/cluster/proxy.js'

/**
 * The cluster's proxy hands a WebSocket's connection to the process that
 * serves it (server/cluster/socket-handoff.js) instead of piping its
 * frames: the process sees the client's own TCP connection, with the head
 * the proxy rewrote (X-Forwarded-For set), and frames flow both ways.
 */
const CHILD = fileURLToPath(new URL('./helpers/handoff-child.js', import.meta.url))

const cleanups = []
afterEach(async () => {
  for (const cleanup of cleanups.splice(0).reverse()) await cleanup()
})

async function startChild () {
  const child = fork(CHILD, { stdio: ['ignore', 'inherit', 'inherit', 'ipc'] })
  cleanups.push(() => { child.kill(); return once(child, 'exit') })
  const [message] = await once(child, 'message')
  return { child, port: message.port }
}

async function open (url) {
  const socket = new WebSocket(url, { headers: { 'X-Forwarded-For': '6.6.6.6' } })
  const [data] = await once(socket, 'message')
  return { socket, hello: JSON.parse(data) }
}

describe('socket hand-off', () => {
  it('gives the process the client\'s own connection, its head rewritten, and counts it until the process says it closed', async () => {
    const processes = [await startChild(), await startChild()]
    const proxy = createProxy({ targets: processes.map(({ child, port }) => ({ host: '127.0.0.1', port, child })), log: { warn () {} } })
    proxy.listen(0, '127.0.0.1')
    await once(proxy, 'listening')
    cleanups.push(() => new Promise((resolve) => { proxy.closeAllConnections?.(); proxy.close(resolve) }))
    const base = `ws://127.0.0.1:${proxy.address().port}`

    const first = await open(`${base}/n/1/ws?token=abc`)
    cleanups.push(() => first.socket.terminate())
    expect(first.hello).toMatchObject({ pid: processes[1].child.pid, url: '/ws?token=abc', forwardedFor: '127.0.0.1' })
    // Handed over, not piped: the process's peer is the client's socket itself.
    expect(first.hello.remotePort).toBe(first.socket._socket.localPort)
    first.socket.send('ping through the hand-off')
    expect(String((await once(first.socket, 'message'))[0])).toBe('ping through the hand-off')

    // Least connections counts handed-over sockets: with process 1's first one, three more make two each.
    const next = []
    for (let i = 0; i < 3; i++) next.push(await open(`${base}/ws`))
    cleanups.push(() => { for (const { socket } of next) socket.terminate() })
    const on = (pid) => next.filter(({ hello }) => hello.pid === pid).length
    expect([on(processes[0].child.pid), on(processes[1].child.pid)]).toEqual([2, 1])

    // Once process 1's first socket has closed (and it said so), the next socket goes there.
    const closed = new Promise((resolve) => processes[1].child.once('message', resolve))
    first.socket.close()
    expect(await closed).toEqual({ type: 'plinko:socket-closed' })
    const after = await open(`${base}/ws`)
    cleanups.push(() => after.socket.terminate())
    expect(after.hello.pid).toBe(processes[1].child.pid)
  })

  it('pipes to a process it cannot hand a socket to (no IPC channel)', async () => {
    const { child, port } = await startChild()
    const proxy = createProxy({ targets: [{ host: '127.0.0.1', port }], log: { warn () {} } })
    proxy.listen(0, '127.0.0.1')
    await once(proxy, 'listening')
    cleanups.push(() => new Promise((resolve) => { proxy.closeAllConnections?.(); proxy.close(resolve) }))
    const { socket, hello } = await open(`ws://127.0.0.1:${proxy.address().port}/ws`)
    cleanups.push(() => socket.terminate())
    expect(hello).toMatchObject({ pid: child.pid, forwardedFor: '127.0.0.1' })
    expect(hello.remotePort).not.toBe(socket._socket.localPort)
  })
})
