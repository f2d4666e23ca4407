import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { mkdtempSync, readFileSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { startServerProcess } from '../../tools/server-process.js'
import { GameClient } from '../server/helpers/game-client.js'
import { floodInThread } from './helpers/flooders.js'

/**
 * A frame flood (issue #14, item 2; issue #21, item 5): raw sockets from one
 * address that never read and send `ping` frames (small, or padded to 4 KB)
 * as fast as they can. Each gets one E_RATE_LIMITED and is closed with 1008;
 * the server stops reading it at once and destroys it within DROP_GRACE_MS.
 * The address's frame and byte budget (WS_IP_MESSAGE_RATE, WS_IP_BYTE_RATE)
 * is shared by all its sockets, so how much of the flood the server handles
 * before every flooder is cut off is bounded by it, however many sockets
 * share it; an honest player on the same address (whose pings stay within
 * its own socket's rate) meanwhile gets every answer and every drop settled
 * (ticks dropped and its ping latency are printed for the record). Run the
 * issue's 12 s with PLINKO_FLOOD_SECONDS=12 (figures printed;
 * docs/hardening.md quotes them).
 */
const FLOOD_MS = Number(process.env.PLINKO_FLOOD_SECONDS ?? 3) * 1000
const MAX_SOCKETS = 64
/** The defaults (server/config.js), spelled out: the bound below is computed from them. */
const IP_MESSAGE_RATE = 500
const IP_BYTE_RATE = 262144
/** Frames a socket may still send once its address's budget is spent if it never went past its own rate (ip-limits.js). */
const QUIET_SLACK = 10
const dir = mkdtempSync(join(tmpdir(), 'plinko-flood-'))
let proc
let port

beforeAll(async () => {
  proc = startServerProcess(`sqlite:${join(dir, 'ledger.sqlite')}`, {
    HTTP_RATE_LIMIT: '1000000',
    SESSION_RATE_LIMIT: '1000000',
    WS_MAX_CONNECTIONS_PER_IP: String(MAX_SOCKETS + 1),
    WS_IP_MESSAGE_RATE: String(IP_MESSAGE_RATE),
    WS_IP_BYTE_RATE: String(IP_BYTE_RATE),
    CLIENT_DIR: '/nonexistent/plinko-client'
  })
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

/** CPU seconds the server process has used (user + system, from /proc; NaN where there is none). */
function serverCpuSeconds () {
  try {
    const fields = readFileSync(`/proc/${proc.child.pid}/stat`, 'utf8').split(') ')[1].split(' ')
    return (Number(fields[11]) + Number(fields[12])) / 100
  } catch {
    return NaN
  }
}

async function metrics () {
  const text = await (await fetch(`http://127.0.0.1:${port}/metrics`)).text()
  let handled = 0
  for (const [, type, n] of text.matchAll(/^plinko_ws_messages_in_total\{type="([^"]+)"\} (\d+)/gm)) if (type !== 'rate_limited') handled += Number(n)
  return { ticksDropped: Number(/^plinko_ticks_dropped_total (\d+)/m.exec(text)[1]), handled }
}

function percentile (values, p) {
  const sorted = [...values].sort((a, b) => a - b)
  return sorted[Math.min(sorted.length - 1, Math.floor(sorted.length * p))]
}

describe.each([
  { sockets: 4, frameBytes: 15 },
  { sockets: 16, frameBytes: 15 },
  { sockets: 64, frameBytes: 15 },
  { sockets: 16, frameBytes: 4000 }
])('a flood of $sockets sockets that never read, $frameBytes-byte frames', ({ sockets, frameBytes }) => {
  it('cuts every flooder off within the address\'s budget while an honest player gets every answer and every drop settled', async () => {
    const honest = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${(await session()).token}`)
    honest.send({ type: 'join', room: '16-medium' })
    await honest.take('joined')
    const tokens = await Promise.all(Array.from({ length: sockets }, async () => (await session()).token))
    const before = await metrics()
    const cpuBefore = serverCpuSeconds()
    // On their own thread: pumping 64 sockets must not delay the honest player's own event loop here.
    const floods = floodInThread({ port, tokens, ms: FLOOD_MS + 5000, frameBytes })
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
    const results = await floods
    const cpu = serverCpuSeconds() - cpuBefore
    for (const ref of drops) {
      const dropped = await honest.take((m) => m.type === 'dropped' && m.ref === ref)
      await honest.take((m) => m.type === 'settled' && m.dropId === dropped.dropId)
    }
    const after = await metrics()
    const dropped = after.ticksDropped - before.ticksDropped
    // The honest player's own frames are in the count too.
    const handled = after.handled - before.handled - rtts.length - drops.length
    const cutOff = results.map((r) => Math.round(r.ms)).sort((a, b) => a - b)
    console.info(`[flood] ${sockets} sockets × ${frameBytes}-byte frames, ${FLOOD_MS / 1000} s: flooders cut off after ${cutOff[0]}–${cutOff.at(-1)} ms, ${handled} of their frames handled, server CPU ${cpu.toFixed(2)} s ` +
      `(${Math.round(Math.max(...results.map((r) => r.bytes)) / 1024)} KB written at most); honest ping p50 ${percentile(rtts, 0.5).toFixed(1)} ms, ` +
      `p99 ${percentile(rtts, 0.99).toFixed(1)} ms, max ${Math.max(...rtts).toFixed(1)} ms over ${rtts.length} pings; ${dropped} ticks dropped; ${drops.length} drops settled`)
    for (const result of results) expect(result.how).toBe('closed by the server')
    // However many sockets: no more than the address's burst (in frames and in bytes) and what refilled while
    // the flooders lived, plus a few frames each.
    const addressBurst = Math.min(2 * IP_MESSAGE_RATE, Math.ceil(2 * IP_BYTE_RATE / frameBytes))
    const refilled = Math.min(IP_MESSAGE_RATE, IP_BYTE_RATE / frameBytes) * cutOff.at(-1) / 1000
    expect(handled).toBeLessThanOrEqual(addressBurst + refilled + sockets * (frameBytes <= 1024 ? QUIET_SLACK + 1 : 1))
    // Ticks dropped and the honest ping's latency are printed, not asserted: on two shared cores they are
    // the machine's as much as the server's (the quiet-machine figures are in docs/hardening.md). What the
    // server guarantees is asserted: every honest answer, every honest drop settled, the flood bounded.
    expect(honest.closeEvent).toBeNull()
    expect(honest.messages.some((m) => m.type === 'error')).toBe(false)
    await honest.close()
  }, 60_000)
})
