import { describe, it, expect, afterEach } from 'vitest'
import http from 'node:http'
import { once } from 'node:events'
import WebSocket, { WebSocketServer } from 'ws'
import { createProxy } from '../../server/cluster/proxy.js'

/**
 * The cluster's proxy (npm run cluster) spreads connections like nginx's
 * least_conn: a player that asks for a session and then opens its socket,
 * as the page and the load generators do, must not put every socket on
 * the same process (a round robin over requests did exactly that).
 */
async function upstream (name) {
  const server = http.createServer((request, response) => response.end(JSON.stringify({ name, path: request.url })))
  const sockets = new WebSocketServer({ server })
  sockets.on('connection', (socket, request) => socket.send(JSON.stringify({ name, path: request.url })))
  server.listen(0, '127.0.0.1')
  await once(server, 'listening')
  return { name, server, sockets, port: server.address().port }
}

const cleanups = []
afterEach(async () => {
  for (const cleanup of cleanups.splice(0).reverse()) await cleanup()
})

describe('cluster proxy balancing', () => {
  it('puts the sockets of players who make a request before each socket on both processes evenly', async () => {
    const processes = [await upstream('a'), await upstream('b')]
    for (const p of processes) cleanups.push(() => new Promise((resolve) => { for (const c of p.sockets.clients) c.terminate(); p.sockets.close(); p.server.close(resolve) }))
    const proxy = createProxy({ targets: processes.map((p) => ({ host: '127.0.0.1', port: p.port })), log: { warn () {} } })
    proxy.listen(0, '127.0.0.1')
    await once(proxy, 'listening')
    cleanups.push(() => new Promise((resolve) => { proxy.closeAllConnections?.(); proxy.close(resolve) }))
    const base = `127.0.0.1:${proxy.address().port}`

    const sockets = []
    const where = { a: 0, b: 0 }
    for (let player = 0; player < 10; player++) {
      await (await fetch(`http://${base}/api/session`, { method: 'POST' })).text()
      const socket = new WebSocket(`ws://${base}/ws?token=t${player}`)
      sockets.push(socket)
      const [data] = await once(socket, 'message')
      const hello = JSON.parse(data)
      expect(hello.path).toBe(`/ws?token=t${player}`)
      where[hello.name]++
    }
    cleanups.push(() => { for (const socket of sockets) socket.terminate() })
    expect(where).toEqual({ a: 5, b: 5 })

    // /n/i/ still goes to process i, whatever the balance.
    for (let i = 0; i < 3; i++) expect(await (await fetch(`http://${base}/n/1/api/rooms`)).json()).toEqual({ name: 'b', path: '/api/rooms' })
    const pinned = new WebSocket(`ws://${base}/n/0/ws`)
    sockets.push(pinned)
    expect(JSON.parse((await once(pinned, 'message'))[0])).toEqual({ name: 'a', path: '/ws' })
  })
})
