import http from 'node:http'
import net from 'node:net'
import { canHandOff, handOff, HANDOFF_CLOSED } from './socket-handoff.js'

/**
 * A small HTTP + WebSocket proxy in front of N server processes on one port
 * (what `npm run cluster` runs; in Docker, nginx does the same job — see
 * deploy/nginx.conf). Two kinds of routes:
 *
 *   /n/{i}/…  → process i, prefix stripped: a process's PUBLIC_URL is
 *               http://HOST:PORT/n/{i}, so an E_WRONG_NODE `owner` leads the
 *               client to the process that runs its room, through this port.
 *   anything else → the process with the fewest open connections through
 *               this proxy (nginx's least_conn, as in deploy/nginx.conf),
 *               ties taken in turn. A plain round robin put every
 *               WebSocket of a client that makes one HTTP request before
 *               each socket (session, then /ws) on the same process.
 *
 * A WebSocket upgrade to a process this proxy started (a target with a
 * `child` that has an IPC channel, as in scripts/cluster.js) is handed
 * over: the socket itself goes to that process (socket-handoff.js), and the
 * proxy carries none of its frames. To any other target it is piped as raw
 * TCP after the request head.
 *
 * The processes learn the client's address from X-Forwarded-For, which this
 * proxy sets to the peer it sees, replacing whatever the client sent (a
 * client-written X-Forwarded-For would let it pick its own address and so
 * evade every per-IP limit); the processes trust exactly this one hop
 * (TRUST_PROXY=loopback in scripts/cluster.js).
 */
/** Request headers a client could use to claim another address: never passed on. */
const FORWARDING_HEADERS = new Set(['x-forwarded-for', 'forwarded', 'x-real-ip'])

function withoutForwarding (headers) {
  const kept = {}
  for (const [name, value] of Object.entries(headers)) if (!FORWARDING_HEADERS.has(name)) kept[name] = value
  return kept
}

/**
 * @param {object} options
 * @param {{ host: string, port: number, child?: import('node:child_process').ChildProcess | null }[]} options.targets
 *   the processes, in /n/{i} order; `child` (read at each upgrade: a restarted worker replaces it) takes WebSockets by hand-off
 * @param {{ warn?: Function }} [options.log]
 */
export function createProxy ({ targets, log = console }) {
  /** Open requests and WebSockets through this proxy, per process. */
  const open = targets.map(() => 0)
  let turn = 0
  /** The least busy process, the turn's first on a tie. */
  const leastConnected = () => {
    let best = turn % targets.length
    for (let k = 1; k < targets.length; k++) {
      const i = (turn + k) % targets.length
      if (open[i] < open[best]) best = i
    }
    turn++
    return best
  }
  const route = (url) => {
    const match = /^\/n\/(\d+)(\/.*)?$/.exec(url.split('?')[0])
    if (match) {
      const index = Number(match[1])
      if (index >= targets.length) return null
      const rest = url.slice(`/n/${index}`.length) || '/'
      return { index, target: targets[index], path: rest.startsWith('/') ? rest : '/' + rest }
    }
    const index = leastConnected()
    return { index, target: targets[index], path: url }
  }
  /** Counts a connection to process `index` as open until `emitter` closes. */
  const track = (index, emitter) => {
    open[index]++
    emitter.once('close', () => { open[index]-- })
  }
  /** Sockets handed to each child and not yet closed there (it says so), for the counts above. */
  const handedOff = new Map()
  const handOffCounted = (index, child, socket, head) => {
    let entry = handedOff.get(child)
    if (!entry) {
      entry = { open: 0 }
      handedOff.set(child, entry)
      child.on('message', (message) => {
        if (message?.type === HANDOFF_CLOSED && entry.open > 0) { entry.open--; open[index]-- }
      })
      // A process that exits takes its sockets with it.
      child.once('exit', () => { open[index] -= entry.open; entry.open = 0; handedOff.delete(child) })
    }
    entry.open++
    open[index]++
    handOff(child, socket, head, (error) => {
      entry.open--
      open[index]--
      log.warn?.(`proxy: could not hand a socket to process ${index}: ${error.message}`)
    })
  }

  const server = http.createServer((request, response) => {
    const routed = route(request.url)
    if (!routed) { response.writeHead(404, { 'content-type': 'application/json' }).end('{"code":"E_NOT_FOUND","message":"no such process"}'); return }
    track(routed.index, response)
    const upstream = http.request({
      host: routed.target.host,
      port: routed.target.port,
      method: request.method,
      path: routed.path,
      headers: { ...withoutForwarding(request.headers), 'x-forwarded-for': request.socket.remoteAddress }
    }, (reply) => {
      response.writeHead(reply.statusCode, reply.headers)
      reply.pipe(response)
    })
    upstream.on('error', (error) => {
      log.warn?.(`proxy: ${routed.target.host}:${routed.target.port} ${error.message}`)
      if (!response.headersSent) response.writeHead(502, { 'content-type': 'application/json' })
      response.end('{"code":"E_UNAVAILABLE","message":"server process unavailable"}')
    })
    request.pipe(upstream)
  })

  server.on('upgrade', (request, socket, head) => {
    const routed = route(request.url)
    if (!routed) { socket.end('HTTP/1.1 404 Not Found\r\n\r\n'); return }
    const lines = [`${request.method} ${routed.path} HTTP/1.1`]
    for (let i = 0; i < request.rawHeaders.length; i += 2) {
      if (!FORWARDING_HEADERS.has(request.rawHeaders[i].toLowerCase())) lines.push(`${request.rawHeaders[i]}: ${request.rawHeaders[i + 1]}`)
    }
    lines.push(`X-Forwarded-For: ${request.socket.remoteAddress}`)
    // The parser decoded the head as latin1: encoded back the same way, every byte is as the client sent it.
    const upstreamHead = Buffer.from(lines.join('\r\n') + '\r\n\r\n', 'latin1')
    const child = routed.target.child
    if (canHandOff(child)) return handOffCounted(routed.index, child, socket, head?.length ? Buffer.concat([upstreamHead, head]) : upstreamHead)
    track(routed.index, socket)
    const upstream = net.connect(routed.target.port, routed.target.host, () => {
      upstream.write(upstreamHead)
      if (head?.length) upstream.write(head)
      upstream.pipe(socket)
      socket.pipe(upstream)
    })
    const fail = () => { socket.destroy(); upstream.destroy() }
    upstream.on('error', fail)
    socket.on('error', fail)
    upstream.on('close', () => socket.destroy())
    socket.on('close', () => upstream.destroy())
  })
  return server
}
