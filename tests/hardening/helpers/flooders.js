import { randomBytes } from 'node:crypto'
import net from 'node:net'
import { Worker, isMainThread, parentPort, workerData } from 'node:worker_threads'

/**
 * Frame flooders for tests/hardening/ws-flood.test.js, run on a worker
 * thread of their own: the test's honest player measures the server's
 * latency, not that of an event loop busy writing to 64 sockets.
 */

/**
 * Starts one flooder per token on a new thread; resolves with each one's
 * { how, ms, bytes }.
 * @param {{ port: number, tokens: string[], ms: number, frameBytes: number }} options
 */
export function floodInThread (options) {
  return new Promise((resolve, reject) => {
    const worker = new Worker(new URL(import.meta.url), { workerData: { flood: options } })
    worker.once('message', resolve)
    worker.once('error', reject)
  })
}

if (!isMainThread && workerData?.flood) {
  const { port, tokens, ms, frameBytes } = workerData.flood
  Promise.all(tokens.map((token) => flooder(port, token, ms, frameBytes))).then((results) => parentPort.postMessage(results))
}

/** One masked client text frame. */
function frame (text) {
  const payload = Buffer.from(text)
  const mask = randomBytes(4)
  const masked = Buffer.from(payload.map((b, i) => b ^ mask[i & 3]))
  const header = payload.length < 126
    ? Buffer.from([0x81, 0x80 | payload.length])
    : Buffer.from([0x81, 0x80 | 126, payload.length >> 8, payload.length & 0xff])
  return Buffer.concat([header, mask, masked])
}

/** A ping, padded with an unknown field to `bytes` (refused as E_BAD_MESSAGE once parsed). */
function pingOf (bytes) {
  const small = '{"type":"ping"}'
  return bytes <= small.length ? small : `{"type":"ping","pad":"${'x'.repeat(bytes - small.length - 9)}"}`
}

/**
 * A flooder: upgrades with a token, never reads a byte of the reply, and
 * writes ping frames until the server cuts it off or `ms` pass. Resolves
 * with how long it lasted and how much it got to write.
 */
function flooder (port, token, ms, frameBytes) {
  return new Promise((resolve) => {
    const socket = net.connect(port, '127.0.0.1')
    const started = performance.now()
    let written = 0
    let done = false
    const one = frame(pingOf(frameBytes))
    const chunk = Buffer.concat(Array.from({ length: Math.max(1, Math.floor(16384 / one.length)) }, () => one))
    const finish = (how) => {
      if (done) return
      done = true
      clearTimeout(timer)
      socket.destroy()
      resolve({ how, ms: performance.now() - started, bytes: written })
    }
    const timer = setTimeout(() => finish('still open'), ms)
    socket.on('error', () => finish('closed by the server'))
    socket.on('close', () => finish('closed by the server'))
    socket.on('connect', () => {
      socket.write(`GET /ws?token=${token} HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Key: ${randomBytes(16).toString('base64')}\r\n\r\n`)
      socket.pause() // never reads
      const pump = () => {
        while (!done) {
          written += chunk.length
          if (!socket.write(chunk)) { socket.once('drain', pump); return }
        }
      }
      setTimeout(pump, 50)
    })
  })
}
