#!/usr/bin/env node
/**
 * Snapshot bandwidth benchmark: `node bench/server-snapshots.js [--quick]`.
 *
 * A real server (buildApp, SQLite ledger in a temp dir, real 60 Hz clock,
 * SNAPSHOT_HZ=20) and two real WebSocket clients on loopback in one room on
 * the 16-row board: a player who keeps 50 balls in flight (dropping again
 * each time one of its balls settles) and an observer who only watches.
 * Counts what the observer receives: binary room frames (the snapshot, with
 * the other players' `dropped`/`settled` events of the period in front of
 * it), payload and WebSocket framing, and the bytes read from its TCP
 * socket. Goal: snapshots < 4 KB/s per client.
 * Exit code 0 whatever the figures.
 */
import WebSocket from 'ws'
import { buildApp } from '../server/app.js'
import { withBenchLedger } from './temp-ledger.js'
import { decodeSnapshot, splitRoomFrame } from '../protocol/snapshot-codec.js'
import { formatTable, fixed, int } from '../cli/text-table.js'

const BALLS = 50
const ROOM = '16-medium'
const GOAL_BYTES_PER_SECOND = 4000
const USAGE = 'usage: node bench/server-snapshots.js [--quick]'

const args = process.argv.slice(2)
for (const arg of args) {
  if (arg === '--help' || arg === '-h') { console.log(USAGE); process.exit(0) }
  if (arg !== '--quick') { console.error(`unknown argument ${arg}\n${USAGE}`); process.exit(2) }
}
const quick = args.includes('--quick')
const WARMUP_SECONDS = quick ? 5 : 8
const MEASURE_SECONDS = quick ? 5 : 30

await withBenchLedger({ SNAPSHOT_HZ: '20', DROP_RATE: '100', DROP_BURST: '100' }, run)

/** @param {import('../server/config.js').Config} config */
async function run (config) {
  const app = await buildApp(config, { logger: false })
  await app.listen({ port: 0, host: '127.0.0.1' })
  const { port } = app.server.address()
  const session = async () => (await app.inject({ method: 'POST', url: '/api/session' })).json()

  const player = await connect(port, (await session()).token)
  const observer = await connect(port, (await session()).token)
  let keepDropping = true
  player.onMessage = (message) => {
    if (message.type === 'settled' && message.player === player.playerId && keepDropping) player.send({ type: 'drop', bet: 1 })
  }
  // Fill the room over ~3 s so landings (and re-drops) spread out.
  for (let i = 0; i < BALLS; i++) {
    player.send({ type: 'drop', bet: 1 })
    await sleep(60)
  }
  await sleep(WARMUP_SECONDS * 1000)

  observer.reset()
  const started = performance.now()
  await sleep(MEASURE_SECONDS * 1000)
  const seconds = (performance.now() - started) / 1000
  const seen = observer.reset()
  keepDropping = false
  player.close()
  observer.close()
  await app.close()

  const perSecond = (n) => n / seconds
  const snapshotWire = seen.snapshotBytes + seen.snapshotFraming
  console.log(`\nServer snapshots: one room (${ROOM}) with ${BALLS} balls kept in flight, SNAPSHOT_HZ=${config.snapshotHz}, an observing client on loopback; ` +
    `${fixed(seconds, 1)} s measured after ${WARMUP_SECONDS} s warm-up${quick ? ' (--quick)' : ''}\n`)
  console.log(formatTable(
    [{ title: 'per client', align: 'left' }, { title: 'value' }, { title: 'note', align: 'left' }],
    [
      ['snapshots per second', fixed(perSecond(seen.snapshots), 1), ''],
      ['balls per snapshot (mean)', fixed(seen.balls / Math.max(1, seen.snapshots), 1), ''],
      ['bytes per snapshot (mean payload)', fixed(seen.snapshotBytes / Math.max(1, seen.snapshots), 1), '7 header + bitmask + 22 bits per ball'],
      ['snapshot bytes/s incl. WS framing', int(perSecond(snapshotWire)), `goal < ${int(GOAL_BYTES_PER_SECOND)}: ${perSecond(snapshotWire) < GOAL_BYTES_PER_SECOND ? 'met' : 'NOT met'}`],
      ['events per second', fixed(perSecond(seen.events), 1), 'dropped + settled of other players\' balls, in the room frames'],
      ['event bytes/s', int(perSecond(seen.eventBytes)), 'JSON; grows with drops per second, not balls'],
      ['frames per second (all kinds)', fixed(perSecond(seen.frames), 1), 'room frames + JSON messages: one frame per snapshot carries the events'],
      ['TCP bytes/s read (everything)', int(perSecond(seen.wireBytes)), '']
    ]
  ))
}

/** A protocol client that tallies what it receives. */
async function connect (port, token) {
  const socket = new WebSocket(`ws://127.0.0.1:${port}/ws?token=${token}`)
  const client = {
    playerId: null,
    onMessage: () => {},
    send: (message) => socket.send(JSON.stringify(message)),
    close: () => socket.close(),
    counts: null,
    wireMark: 0,
    /** Returns the tallies since the last reset and starts new ones. */
    reset () {
      const counts = client.counts
      const wire = socket._socket?.bytesRead ?? 0
      if (counts) counts.wireBytes = wire - client.wireMark
      client.wireMark = wire
      client.counts = { snapshots: 0, balls: 0, snapshotBytes: 0, snapshotFraming: 0, events: 0, eventBytes: 0, frames: 0, wireBytes: 0 }
      return counts
    }
  }
  client.reset()
  // Listen before 'open': the welcome can arrive in the same packet as the upgrade.
  const opened = new Promise((resolve, reject) => { socket.once('open', resolve); socket.once('error', reject) })
  const joined = new Promise((resolve) => {
    socket.on('message', (data, isBinary) => {
      const counts = client.counts
      counts.frames++
      if (isBinary) {
        const { events, snapshot } = splitRoomFrame(data)
        counts.snapshots++
        counts.balls += decodeSnapshot(snapshot).balls.length
        counts.snapshotBytes += snapshot.length
        counts.snapshotFraming += framing(data.length)
        counts.events += events.length
        counts.eventBytes += data.length - snapshot.length
        for (const event of events) if (event.player !== client.playerId) client.onMessage(event) // own events come on their own
        return
      }
      const message = JSON.parse(data.toString())
      if (message.type === 'welcome') {
        client.playerId = message.playerId
        client.send({ type: 'join', room: ROOM })
      }
      if (message.type === 'joined') resolve()
      if (message.type === 'events') {
        counts.events += message.events.length
        counts.eventBytes += data.length
      }
      client.onMessage(message)
    })
  })
  await opened
  await joined
  client.reset()
  return client
}

/** Bytes a server adds around a WebSocket message payload (unmasked). */
function framing (length) {
  return length < 126 ? 2 : length < 65536 ? 4 : 10
}

function sleep (ms) {
  return new Promise((resolve) => setTimeout(resolve, ms))
}
