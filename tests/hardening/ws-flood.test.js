import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { randomBytes } from 'node:crypto'
import { mkdtempSync, rmSync } from 'node:fs'
import net from 'node:net'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { startServerProcess } from '../../tools/server-process.js'
import { GameClient } from '../server/helpers/game-client.js'

/**
 * A frame flood (issue #14, item 2): raw sockets from one address that
 * never read and send small `ping` frames as fast as they can. Each gets
 * one E_RATE_LIMITED and is closed with 1008; the server stops reading it at
 * once and destroys it within DROP_GRACE_MS, so an honest player in a room
 * meanwhile sees every tick and every answer. Run the 12 s with
 * PLINKO_FLOOD_SECONDS=12 (figures printed; the README quotes them).
 */
const FLOOD_MS = Number(process.env.PLINKO_FLOOD_SECONDS ?? 3) * 1000
const dir = mkdtempSync(join(tmpdir(), 'plinko-flood-'))
let proc
let port

beforeAll(async () => {
  proc = startServerProcess(`sqlite:${join(dir, 'ledger.sqlite')}`, { HTTP_RATE_LIMIT: '1000000', SESSION_RATE_LIMIT: '1000000', CLIENT_DIR: '/nonexistent/plinko-client' })
  port = await proc.port
})
afterAll(async () => {
  proc?.child.kill('SIGTERM')
  await proc?.exited
  rmSync(dir, { recursive: true, force: true })
})

async function session () {
  return (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
}

async function ticksDropped () {
  const text = await (await fetch(`http://127.0.0.1:${port}/metrics`)).text()
  return Number(/^plinko_ticks_dropped_total (\d+)/m.exec(text)[1])
}

/** One masked client text frame. */
function frame (text) {
  const payload = Buffer.from(text)
  const mask = randomBytes(4)
  const masked = Buffer.from(payload.map((b, i) => b ^ mask[i & 3]))
  return Buffer.concat([Buffer.from([0x81, 0x80 | payload.length]), mask, masked])
}

/**
 * A flooder: upgrades with a token, never reads a byte of the reply, and
 * writes ping frames until the server cuts it off or `ms` pass. Resolves
 * with how long it lasted and how much it got to write.
 */
function flooder (token, ms) {
  return new Promise((resolve) => {
    const socket = net.connect(port, '127.0.0.1')
    const started = performance.now()
    let written = 0
    let done = false
    const chunk = Buffer.concat(Array.from({ length: 512 }, () => frame('{"type":"ping"}')))
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

function percentile (values, p) {
  const sorted = [...values].sort((a, b) => a - b)
  return sorted[Math.min(sorted.length - 1, Math.floor(sorted.length * p))]
}

describe.each([4, 16])('a flood of %i sockets that never read', (sockets) => {
  it('cuts every flooder off at once while an honest player keeps every tick and every answer', async () => {
    const honest = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${(await session()).token}`)
    honest.send({ type: 'join', room: '16-medium' })
    await honest.take('joined')
    const droppedBefore = await ticksDropped()
    const tokens = await Promise.all(Array.from({ length: sockets }, async () => (await session()).token))
    const floods = tokens.map((token) => flooder(token, FLOOD_MS + 5000))
    // The honest player pings every 20 ms and drops a ball every 250 ms while the flood lasts.
    const rtts = []
    const drops = []
    const until = performance.now() + FLOOD_MS
    for (let i = 0; performance.now() < until; i++) {
      const sent = performance.now()
      honest.send({ type: 'ping', ref: `p${i}` })
      await honest.take((m) => m.type === 'pong' && m.ref === `p${i}`)
      rtts.push(performance.now() - sent)
      if (i % 12 === 0) { honest.send({ type: 'drop', bet: 1, ref: `d${i}` }); drops.push(`d${i}`) }
      await new Promise((resolve) => setTimeout(resolve, 20))
    }
    const results = await Promise.all(floods)
    for (const ref of drops) {
      const dropped = await honest.take((m) => m.type === 'dropped' && m.ref === ref)
      await honest.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    }
    const dropped = (await ticksDropped()) - droppedBefore
    console.info(`[flood] ${sockets} sockets, ${FLOOD_MS / 1000} s: flooders cut off after ${results.map((r) => Math.round(r.ms)).join(', ')} ms ` +
      `(${Math.round(Math.max(...results.map((r) => r.bytes)) / 1024)} KB written at most); honest ping p50 ${percentile(rtts, 0.5).toFixed(1)} ms, ` +
      `p99 ${percentile(rtts, 0.99).toFixed(1)} ms, max ${Math.max(...rtts).toFixed(1)} ms over ${rtts.length} pings; ${dropped} ticks dropped; ${drops.length} drops settled`)
    for (const result of results) expect(result.how).toBe('closed by the server')
    expect(dropped).toBe(0)
    expect(honest.closeEvent).toBeNull()
    expect(honest.messages.some((m) => m.type === 'error')).toBe(false)
    await honest.close()
  }, 60_000)
})
