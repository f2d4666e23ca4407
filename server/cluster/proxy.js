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
 * @typedef {{ host: string, port: number, child?: import('node:child_process').ChildProcess | null }} ProxyTarget
 */

/**
 * @param {object} options
 * @param {ProxyTarget[]} options.targets
 *   the processes, in /n/{i} order; `child` (read at each upgrade: a restarted worker replaces it) takes WebSockets by hand-off
 * @param {{ warn: Function }} [options.log] (console by default)
 */
export function createProxy ({ targets, log = console }) {
  const balance = new ConnectionBalance(targets, log)
  const server = http.createServer((request, response) => forwardRequest(balance, request, response, log))
  server.on('upgrade', (request, socket, head) => forwardUpgrade(balance, request, socket, head))
  return server
}

/**
 * Which process a request goes to, and how many connections each has open
 * through this proxy (requests, piped WebSockets, and sockets handed to a
 * child until it says they closed).
 */
class ConnectionBalance {
  /** @param {ProxyTarget[]} targets @param {{ warn: Function }} log */
  constructor (targets, log) {
    this.targets = targets
    this.log = log
    /** Open requests and WebSockets through this proxy, per process. */
    this.open = targets.map(() => 0)
    this.turn = 0
    /** Sockets handed to each child and not yet closed there. */
    this.handedOff = new Map()
  }

  /** The least busy process, the turn's first on a tie. */
  leastConnected () {
    const { open, targets } = this
    let best = this.turn % targets.length
    for (let k = 1; k < targets.length; k++) {
      const i = (this.turn + k) % targets.length
      if (open[i] < open[best]) best = i
    }
    this.turn++
    return best
  }

  /** @param {string} url @returns {{ index: number, target: ProxyTarget, path: string } | null} null: no such process */
  route (url) {
    const match = /^\/n\/(\d+)(\/.*)?$/.exec(url.split('?')[0])
    if (match) {
      const index = Number(match[1])
      if (index >= this.targets.length) return null
      const rest = url.slice(`/n/${index}`.length) || '/'
      return { index, target: this.targets[index], path: rest.startsWith('/') ? rest : '/' + rest }
    }
    const index = this.leastConnected()
    return { index, target: this.targets[index], path: url }
  }

  /** Counts a connection to process `index` as open until `emitter` closes. */
  track (index, emitter) {
    this.open[index]++
    emitter.once('close', () => { this.open[index]-- })
  }

  /** Hands `socket` to `child` (process `index`), counted open until the child reports it closed or exits. */
  handOff (index, child, socket, head) {
    const counted = this._handedOffTo(index, child)
    counted.open++
    this.open[index]++
    handOff(child, socket, head, (error) => {
      counted.open--
      this.open[index]--
      this.log.warn(`proxy: could not hand a socket to process ${index}: ${error.message}`)
    })
  }

  /** The count of sockets handed to `child`, kept by its messages and its exit. */
  _handedOffTo (index, child) {
    let counted = this.handedOff.get(child)
    if (counted) return counted
    counted = { open: 0 }
    this.handedOff.set(child, counted)
    child.on('message', (message) => {
      if (message?.type === HANDOFF_CLOSED && counted.open > 0) { counted.open--; this.open[index]-- }
    })
    // A process that exits takes its sockets with it.
    child.once('exit', () => { this.open[index] -= counted.open; counted.open = 0; this.handedOff.delete(child) })
    return counted
  }
}

/** An HTTP request, to its process, with X-Forwarded-For set to the peer this proxy sees. */
function forwardRequest (balance, request, response, log) {
  const routed = balance.route(request.url)
  if (!routed) { response.writeHead(404, { 'content-type': 'application/json' }).end('{"code":"E_NOT_FOUND","message":"no such process"}'); return }
  balance.track(routed.index, response)
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
    log.warn(`proxy: ${routed.target.host}:${routed.target.port} ${error.message}`)
    if (!response.headersSent) response.writeHead(502, { 'content-type': 'application/json' })
    response.end('{"code":"E_UNAVAILABLE","message":"server process unavailable"}')
  })
  request.pipe(upstream)
}

/** The upgrade request's head as the process gets it: its path, the client's headers less forwarding ones, X-Forwarded-For. */
function upstreamHeadOf (request, path) {
  const lines = [`${request.method} ${path} HTTP/1.1`]
  for (let i = 0; i < request.rawHeaders.length; i += 2) {
    if (!FORWARDING_HEADERS.has(request.rawHeaders[i].toLowerCase())) lines.push(`${request.rawHeaders[i]}: ${request.rawHeaders[i + 1]}`)
  }
  lines.push(`X-Forwarded-For: ${request.socket.remoteAddress}`)
  // The parser decoded the head as latin1: encoded back the same way, every byte is as the client sent it.
  return Buffer.from(lines.join('\r\n') + '\r\n\r\n', 'latin1')
}

/** A WebSocket upgrade: handed to a child process that can take it, piped as raw TCP to any other. */
function forwardUpgrade (balance, request, socket, head) {
  const routed = balance.route(request.url)
  if (!routed) { socket.end('HTTP/1.1 404 Not Found\r\n\r\n'); return }
  const upstreamHead = upstreamHeadOf(request, routed.path)
  const child = routed.target.child
  if (canHandOff(child)) return balance.handOff(routed.index, child, socket, head?.length ? Buffer.concat([upstreamHead, head]) : upstreamHead)
  balance.track(routed.index, socket)
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
}
