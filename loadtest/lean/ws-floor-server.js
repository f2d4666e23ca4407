#!/usr/bin/env node
/**
 * The bare WebSocket floor's server (`node loadtest/lean/ws-floor-server.js
 * [--frame-bytes 190] [--interval-ms 50]`), run by loadtest/lean/measure-server.js (bench/ws-floor.js, the capacity script) as its
 * own process: a `ws` WebSocketServer on 127.0.0.1 (perMessageDeflate off,
 * no game, no ledger, no metrics) that sends the same binary frame to every
 * open socket every interval, and does nothing else. It prints
 * `listening <port>` once ready and `sent <frames>` when it gets SIGTERM.
 * What it costs per frame is the least any Node `ws` game server can cost.
 */
import { parseArgs } from 'node:util'
import { WebSocketServer } from 'ws'

const { values } = parseArgs({ options: { 'frame-bytes': { type: 'string', default: '190' }, 'interval-ms': { type: 'string', default: '50' } } })
const frame = Buffer.alloc(Number(values['frame-bytes']), 0x5a)
frame[0] = 2 // a room frame's kind byte, though nobody decodes it
const server = new WebSocketServer({ host: '127.0.0.1', port: 0, perMessageDeflate: false, clientTracking: true })
let sent = 0
server.on('listening', () => console.log(`listening ${server.address().port}`))
setInterval(() => {
  for (const socket of server.clients) {
    if (socket.readyState !== 1) continue
    socket.send(frame, { binary: true })
    sent++
  }
}, Number(values['interval-ms']))
process.on('SIGTERM', () => {
  console.log(`sent ${sent}`)
  process.exit(0)
})
