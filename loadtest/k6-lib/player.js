/**
 * One virtual player, as a browser plays: POST /api/session, open
 * /ws?token=…, `join` its room, `drop` one ball every DROP_INTERVAL, and
 * check what comes back:
 *
 * - every own `dropped` and `settled` carries the running balance: it must
 *   equal the previous one − bet (dropped) or + payout (settled), starting
 *   from `welcome.balance`, and payout = bet × multiplier exactly (credits
 *   with up to three decimals, compared in milli-credits);
 * - every accepted drop gets its `settled` before the player leaves
 *   (`unsettled_drops` counts the ones that do not);
 * - every error frame, unexpected close or failed request is counted by code;
 * - clustered, a join answered E_WRONG_NODE is followed: the player
 *   reconnects to the `owner` process (loopback only) and joins there.
 *
 * Arrival times come from `event.timestamp` (when k6's reader goroutine got
 * the frame), so time a frame waits for k6's JavaScript event loop is not
 * counted; a k6 short of CPU still delays its reader goroutines, so near
 * k6's own limit the latencies include some of k6 (see RESULTS.md).
 * Snapshots are only counted, and one interval in JITTER_SAMPLE is timed:
 * the k6 side must stay cheap, it shares the CPU with the server.
 */
import http from 'k6/http'
import { check, sleep } from 'k6'
import exec from 'k6/execution'
import { WebSocket } from 'k6/websockets'
import { setTimeout, clearTimeout, setInterval, clearInterval } from 'k6/timers'
import { metrics } from './player-metrics.js'
import { ownerSocketUrl } from './scenario-config.js'
import { decodeOwnMessages } from '../../protocol/drop-events-codec.js'

const TICK_MS = 1000 / 60
const JOIN_TIMEOUT_MS = 30_000
const DRAIN_POLL_MS = 200
const LOGGED_ERRORS_PER_VU = 3
/** E_WRONG_NODE answers followed before joining; one more is an error (two processes disagreeing). */
const MAX_REDIRECTS = 3

/**
 * The rooms the players are spread over: the first `count` ids the server
 * lists (GET /api/rooms, in setup()): one room per board first, then each
 * board's second room, and so on (216 in all); if
 * it offers fewer than `count`, the players share the ones there are (and
 * the report says so: setup data holds the list).
 * @param {string} baseUrl @param {number} count
 * @returns {string[]}
 */
export function chooseRooms (baseUrl, count) {
  const response = http.get(`${baseUrl}/api/rooms`, { tags: { name: 'GET /api/rooms' } })
  if (response.status !== 200) throw new Error(`GET /api/rooms: ${response.status} ${response.body}`)
  const ids = response.json('roomIds')
  if (count > ids.length) console.warn(`ROOMS=${count} but the server offers ${ids.length} rooms: the players share those ${ids.length}`)
  return ids.slice(0, count)
}

/**
 * The scenarios' player: virtual user i plays in room i mod rooms, connects
 * at its share of RAMP, and leaves after DURATION at its share of LEAVE
 * (0 s unless a scenario spreads the leaving, as spike.js does).
 * @param {ReturnType<import('./scenario-config.js').readScenarioConfig>} config
 * @param {string[]} rooms from chooseRooms(), in setup()
 */
export function playScheduledPlayer (config, rooms) {
  const index = exec.vu.idInTest - 1
  const share = index / config.vus
  const rampMs = config.rampS * 1000
  playPlayer(config, rooms[index % rooms.length], {
    connectAtMs: share * rampMs,
    leaveAtMs: rampMs + config.durationS * 1000 + share * config.leaveS * 1000
  })
}

/**
 * Plays one player from `connectAtMs` to `leaveAtMs` (ms after the scenario
 * started), then waits up to `config.drainS` for its last settles.
 * @param {ReturnType<import('./scenario-config.js').readScenarioConfig>} config
 * @param {string} room
 * @param {{ connectAtMs: number, leaveAtMs: number }} schedule
 */
export function playPlayer (config, room, { connectAtMs, leaveAtMs }) {
  const startedAt = exec.scenario.startTime
  const untilConnect = startedAt + connectAtMs - Date.now()
  if (untilConnect > 0) sleep(untilConnect / 1000)

  const session = http.post(`${config.baseUrl}/api/session`, null, { tags: { name: 'POST /api/session' } })
  if (!check(session, { 'session created (201)': (r) => r.status === 201 })) {
    metrics.errors.add(1, { code: `HTTP_${session.status}` })
    logOnce(`POST /api/session: ${session.status} ${String(session.body).slice(0, 200)}`)
    return
  }
  connect(config, room, session.json('token'), startedAt + leaveAtMs)
}

let loggedErrors = 0
function logOnce (text) {
  if (loggedErrors++ < LOGGED_ERRORS_PER_VU) console.warn(`VU ${exec.vu.idInTest}: ${text}`)
}

/**
 * The player's WebSocket, from `welcome` to close. State lives in closure
 * variables, not object properties: k6's JavaScript engine (sobek) looks
 * properties up in a map on every access, and the message handler runs for
 * every frame the server sends (tens of thousands per second). What only
 * the player's own messages touch (a few per second) lives in ownDrops and
 * socketLife.
 */
function connect (config, room, token, leaveAt, wsUrl = config.wsUrl, redirects = 0) {
  const every = config.jitterSampleEvery
  const seeds = config.delivery === 'seeds'
  let playerId = null
  let openedAt = 0
  let jsonMessages = 0
  let jsonBytes = 0
  let frames = 0
  let frameBytes = 0
  let dropEventCount = 0
  let phase = 0

  const ws = new WebSocket(`${wsUrl}?token=${token}`, null, { tags: { name: '/ws' } })
  ws.binaryType = 'arraybuffer'
  const drops = ownDrops(config.bet)
  const sampler = snapshotSampler()
  const life = socketLife(config, ws, drops, leaveAt, {
    redirect: (ownerUrl) => connect(config, room, token, leaveAt, ownerUrl, redirects + 1),
    finished: () => reportTraffic({ seeds, openedAt, jsonMessages, jsonBytes, frames, frameBytes, dropEventCount })
  })
  ws.onopen = () => { openedAt = Date.now() }
  ws.onerror = (event) => life.socketError(event)
  ws.onclose = (event) => life.closed(event.code)
  ws.onmessage = (event) => {
    const data = event.data
    if (typeof data !== 'string') {
      frames++
      frameBytes += data.byteLength
      if (seeds) {
        dropEventCount += countDropEvents(data, (messages) => { for (const message of messages) handle(message, event.timestamp) })
        return
      }
      // Time one pair of consecutive frames in every `every`.
      if (++phase >= every && sampler.sample(data, event.timestamp)) phase = 0
      return
    }
    jsonMessages++
    jsonBytes += data.length
    // Other players' `dropped`/`settled` (most of the traffic) are only counted: they never name us.
    if (playerId !== null && data.indexOf(playerId) === -1 && (data.startsWith('{"type":"dropped"') || data.startsWith('{"type":"settled"'))) return
    receive(data, event.timestamp)
  }

  function receive (data, at) {
    let message
    try {
      message = JSON.parse(data)
    } catch {
      metrics.errors.add(1, { code: 'X_BAD_JSON' })
      return
    }
    handle(message, at)
  }

  function handle (message, at) {
    switch (message.type) {
      case 'welcome':
        playerId = message.playerId
        drops.setBalance(message.balance)
        ws.send(JSON.stringify(seeds ? { type: 'join', room, delivery: 'seeds' } : { type: 'join', room }))
        return
      case 'joined':
        sampler.setSnapshotEvery(message.snapshotEvery)
        return life.joined()
      case 'dropped': if (message.player === playerId) drops.dropped(message, at); return
      case 'settled': if (message.player === playerId) drops.settled(message, at); return
      case 'error':
        if (message.code === 'E_WRONG_NODE' && !life.hasJoined() && redirects < MAX_REDIRECTS && ownerSocketUrl(message.owner) !== null) return life.moveTo(ownerSocketUrl(message.owner))
        return refused(message, drops)
    }
  }
}

/**
 * The socket's life around the game: the join timeout, dropping every
 * DROP_INTERVAL from a random phase once joined, leaving at `leaveAt`
 * (waiting at most DRAIN for the last settles), a redirect to the room's
 * owner, and the close. `finished` is called once, on a close that ends
 * the player (not on a redirect).
 */
function socketLife (config, ws, drops, leaveAt, { redirect, finished }) {
  const interval = config.dropIntervalMs
  let dropTimer = null
  let joinedAt = 0
  let leaving = false
  let closedByUs = false
  let done = false
  const joinTimer = setTimeout(() => {
    if (joinedAt || done) return
    metrics.errors.add(1, { code: 'X_JOIN_TIMEOUT' })
    logOnce(`no welcome/joined within ${JOIN_TIMEOUT_MS} ms`)
    close()
  }, JOIN_TIMEOUT_MS)
  setTimeout(leave, Math.max(0, leaveAt - Date.now()))

  function drop () {
    if (leaving || done) return
    drops.send(ws)
  }

  /** Stops dropping, waits for the last settles (at most DRAIN), then closes. */
  function leave () {
    if (leaving || done) return
    leaving = true
    if (dropTimer !== null) clearInterval(dropTimer)
    const deadline = Date.now() + config.drainS * 1000
    const poll = setInterval(() => {
      if (done || drops.allAnswered() || Date.now() >= deadline) {
        clearInterval(poll)
        close()
      }
    }, DRAIN_POLL_MS)
  }

  function close () {
    if (done) return
    closedByUs = true
    ws.close(1000)
  }

  return {
    hasJoined: () => joinedAt !== 0,
    joined () {
      joinedAt = Date.now()
      clearTimeout(joinTimer)
      if (interval <= 0 || leaving) return
      // A random phase, so the players' drops do not arrive in waves.
      setTimeout(() => {
        if (leaving) return
        drop()
        dropTimer = setInterval(drop, interval)
      }, Math.random() * interval)
    },
    /** Leaves this socket quietly (nothing was dropped on it yet) and plays on from the room's owner. */
    moveTo (ownerUrl) {
      done = true
      closedByUs = true
      clearTimeout(joinTimer)
      metrics.redirects.add(1)
      ws.close(1000)
      redirect(ownerUrl)
    },
    socketError (event) {
      if (closedByUs) return
      metrics.errors.add(1, { code: 'WS_ERROR' })
      logOnce(`websocket error: ${event.error}`)
    },
    closed (code) {
      if (done) return
      done = true
      leaving = true
      clearTimeout(joinTimer)
      if (dropTimer !== null) clearInterval(dropTimer)
      reportClose(code, closedByUs, drops)
      finished()
    }
  }
}

/** A close that ends the player: counted if the server closed, and the drops left unanswered. */
function reportClose (code, closedByUs, drops) {
  if (!closedByUs) {
    metrics.errors.add(1, { code: `WS_CLOSE_${code}` })
    logOnce(`server closed the connection: ${code}`)
  }
  const unsettled = drops.unanswered()
  metrics.unsettledDrops.add(unsettled)
  if (unsettled > 0) logOnce(`${unsettled} drops unsettled when leaving`)
  metrics.errors.add(0)
  metrics.balanceMismatches.add(0)
}

/**
 * The player's own drops: sent, acknowledged (`dropped`), settled, and the
 * running balance each of those carries, checked to the milli-credit.
 * @param {number} bet
 */
function ownDrops (bet) {
  let balance = 0
  let seq = 0
  /** ref → sent at (ms): sent, not yet acknowledged by `dropped` or refused. */
  const pending = new Map()
  /** dropId → sent at (ms): announced, not yet settled. */
  const inFlight = new Map()

  /** @param {number} expected milli-credits */
  function checkBalance (message, expected) {
    if (milli(message.balance) !== expected) {
      metrics.balanceMismatches.add(1)
      metrics.errors.add(1, { code: 'X_BALANCE_MISMATCH' })
      logOnce(`${message.type} ${message.dropId}: balance ${message.balance}, expected ${expected / 1000}`)
    }
    balance = message.balance
  }

  return {
    setBalance (credits) { balance = credits },
    send (ws) {
      const ref = ++seq
      pending.set(ref, Date.now())
      ws.send(JSON.stringify({ type: 'drop', bet, ref }))
      metrics.dropsSent.add(1)
    },
    dropped (message, at) {
      const sentAt = pending.get(message.ref)
      if (sentAt === undefined) {
        metrics.errors.add(1, { code: 'X_UNKNOWN_DROP' })
        logOnce(`dropped ${message.dropId} with ref ${message.ref} that this player did not send`)
      } else {
        pending.delete(message.ref)
        metrics.dropAck.add(at - sentAt)
        inFlight.set(message.dropId, sentAt)
      }
      checkBalance(message, milli(balance) - message.bet * 1000)
    },
    settled (message, at) {
      const sentAt = inFlight.get(message.dropId)
      if (sentAt === undefined) {
        metrics.errors.add(1, { code: 'X_UNKNOWN_SETTLE' })
        logOnce(`settled ${message.dropId} that was never announced to this player`)
      } else {
        inFlight.delete(message.dropId)
        const latency = at - sentAt
        metrics.dropSettled.add(latency)
        // The ball takes its first step on the tick after the drop arrived.
        metrics.dropSettleOverhead.add(latency - (message.ticks - 1) * TICK_MS)
        metrics.dropsSettled.add(1)
      }
      const payout = message.bet * Math.round(message.multiplier * 1000)
      if (milli(message.payout) !== payout) {
        metrics.errors.add(1, { code: 'X_BAD_PAYOUT' })
        logOnce(`drop ${message.dropId}: payout ${message.payout}, expected ${payout / 1000}`)
      }
      checkBalance(message, milli(balance) + milli(message.payout))
    },
    /** A refused drop is never debited or announced. */
    refused (ref) { pending.delete(ref) },
    unanswered: () => pending.size + inFlight.size,
    allAnswered: () => pending.size === 0 && inFlight.size === 0
  }
}

/** An error frame that is not a redirect: counted by code, and a refused drop forgotten. */
function refused (message, drops) {
  metrics.errors.add(1, { code: message.code })
  logOnce(`error ${message.code}: ${message.message}`)
  if (message.ref !== undefined) drops.refused(message.ref)
}

/**
 * Times pairs of consecutive snapshots: `sample` is called on frame
 * `every`·k (it remembers the tick) and the one after (it times the pair and
 * returns true). The tick is the uint32 LE at offset 1 of the snapshot,
 * which a room frame (kind 2: uint32 events length L at offset 1, then L
 * bytes of events) carries at offset 5 + L.
 */
function snapshotSampler () {
  let snapshotEvery = 3
  let sampleTick = -1
  let sampleAt = 0
  return {
    setSnapshotEvery (ticks) { snapshotEvery = ticks },
    sample (buffer, at) {
      const head = new Uint8Array(buffer, 0, 5)
      const start = head[0] === 2 ? 5 + (head[1] | (head[2] << 8) | (head[3] << 16)) + head[4] * 16777216 : 0
      const b = new Uint8Array(buffer, start + 1, 4)
      const tick = (b[0] | (b[1] << 8) | (b[2] << 16)) + b[3] * 16777216
      if (sampleTick < 0) {
        sampleTick = tick
        sampleAt = at
        return false
      }
      const ticks = tick - sampleTick
      if (ticks > 0) {
        const elapsed = at - sampleAt
        if (ticks === snapshotEvery) metrics.snapshotInterval.add(elapsed)
        metrics.snapshotJitter.add(Math.abs(elapsed - ticks * TICK_MS))
      }
      sampleTick = -1
      return true
    }
  }
}

/**
 * Seeds mode: the events in a drop-events frame (protocol/drop-events-codec.js:
 * kind 3, N at offset 13, 15 + 64·N bytes), counted, not decoded (k6's CPU
 * is shared with the server); what follows them is this player's own
 * messages (ASCII JSON array: its `settled`), handed to `own`. Anything else
 * is an error (and counts 0).
 */
function countDropEvents (buffer, own) {
  const bytes = new Uint8Array(buffer)
  if (bytes[0] !== 3) {
    metrics.errors.add(1, { code: 'X_UNEXPECTED_SNAPSHOT' })
    logOnce(`binary frame of kind ${bytes[0]} on a seeds socket`)
    return 0
  }
  const count = bytes.length >= 15 ? bytes[13] | (bytes[14] << 8) : -1
  const end = 15 + 64 * count
  const messages = count < 0 || bytes.length < end ? null : decodeOwnMessages(bytes, end)
  if (messages === null) {
    metrics.errors.add(1, { code: 'X_BAD_FRAME' })
    logOnce(`drop-events frame of ${bytes.length} bytes`)
    return 0
  }
  if (messages.length > 0) own(messages)
  return count
}


/** What the socket received, by kind, and per second of its life. */
function reportTraffic ({ seeds, openedAt, jsonMessages, jsonBytes, frames, frameBytes, dropEventCount }) {
  metrics.messagesReceived.add(jsonMessages, { kind: 'json' })
  const binaryKind = seeds ? 'drop_events' : 'snapshot'
  metrics.messagesReceived.add(frames, { kind: binaryKind })
  metrics.bytesReceived.add(jsonBytes, { kind: 'json' })
  metrics.bytesReceived.add(frameBytes, { kind: binaryKind })
  metrics.dropEventsReceived.add(dropEventCount)
  const seconds = openedAt > 0 ? (Date.now() - openedAt) / 1000 : 0
  if (seconds >= 1) {
    metrics.clientMessagesPerSecond.add((jsonMessages + frames) / seconds)
    metrics.clientBytesPerSecond.add((jsonBytes + frameBytes) / seconds)
  }
}

/** Credits (up to three decimals, as the server sends them) in milli-credits, for exact sums. */
function milli (credits) {
  return Math.round(credits * 1000)
}
