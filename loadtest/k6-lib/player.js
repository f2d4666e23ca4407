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
 * every frame the server sends (tens of thousands per second).
 */
function connect (config, room, token, leaveAt, wsUrl = config.wsUrl, redirects = 0) {
  const every = config.jitterSampleEvery
  const interval = config.dropIntervalMs
  const bet = config.bet
  const seeds = config.delivery === 'seeds'
  let playerId = null
  let balance = 0
  let snapshotEvery = 3
  let seq = 0
  /** ref → sent at (ms): sent, not yet acknowledged by `dropped` or refused. */
  const pending = new Map()
  /** dropId → sent at (ms): announced, not yet settled. */
  const inFlight = new Map()
  let dropTimer = null
  let joinedAt = 0
  let openedAt = 0
  let leaving = false
  let closedByUs = false
  let finished = false
  let jsonMessages = 0
  let jsonBytes = 0
  let frames = 0
  let frameBytes = 0
  let dropEventCount = 0
  let phase = 0
  let sampleTick = -1
  let sampleAt = 0

  const ws = new WebSocket(`${wsUrl}?token=${token}`, null, { tags: { name: '/ws' } })
  ws.binaryType = 'arraybuffer'
  ws.onopen = () => { openedAt = Date.now() }
  ws.onerror = (event) => {
    if (closedByUs) return
    metrics.errors.add(1, { code: 'WS_ERROR' })
    logOnce(`websocket error: ${event.error}`)
  }
  ws.onclose = (event) => closed(event.code)
  ws.onmessage = (event) => {
    const data = event.data
    if (typeof data !== 'string') {
      frames++
      frameBytes += data.byteLength
      if (seeds) return dropEvents(data)
      // Time one pair of consecutive frames in every `every`.
      if (++phase >= every) sampleSnapshot(data, event.timestamp)
      return
    }
    jsonMessages++
    jsonBytes += data.length
    // Other players' `dropped`/`settled` (most of the traffic) are only counted: they never name us.
    if (playerId !== null && data.indexOf(playerId) === -1 && (data.startsWith('{"type":"dropped"') || data.startsWith('{"type":"settled"'))) return
    receive(data, event.timestamp)
  }

  const joinTimer = setTimeout(() => {
    if (joinedAt || finished) return
    metrics.errors.add(1, { code: 'X_JOIN_TIMEOUT' })
    logOnce(`no welcome/joined within ${JOIN_TIMEOUT_MS} ms`)
    close()
  }, JOIN_TIMEOUT_MS)
  setTimeout(leave, Math.max(0, leaveAt - Date.now()))

  function receive (data, at) {
    let message
    try {
      message = JSON.parse(data)
    } catch {
      metrics.errors.add(1, { code: 'X_BAD_JSON' })
      return
    }
    switch (message.type) {
      case 'welcome':
        playerId = message.playerId
        balance = message.balance
        ws.send(JSON.stringify(seeds ? { type: 'join', room, delivery: 'seeds' } : { type: 'join', room }))
        return
      case 'joined': return joined(message)
      case 'dropped': if (message.player === playerId) dropped(message, at); return
      case 'settled': if (message.player === playerId) settled(message, at); return
      case 'error': return error(message)
    }
  }

  function joined (message) {
    joinedAt = Date.now()
    clearTimeout(joinTimer)
    snapshotEvery = message.snapshotEvery
    if (interval <= 0 || leaving) return
    // A random phase, so the players' drops do not arrive in waves.
    setTimeout(() => {
      if (leaving) return
      drop()
      dropTimer = setInterval(drop, interval)
    }, Math.random() * interval)
  }

  function drop () {
    if (leaving || finished) return
    const ref = ++seq
    pending.set(ref, Date.now())
    ws.send(JSON.stringify({ type: 'drop', bet, ref }))
    metrics.dropsSent.add(1)
  }

  function dropped (message, at) {
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
  }

  function settled (message, at) {
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
  }

  /** @param {number} expected milli-credits */
  function checkBalance (message, expected) {
    if (milli(message.balance) !== expected) {
      metrics.balanceMismatches.add(1)
      metrics.errors.add(1, { code: 'X_BALANCE_MISMATCH' })
      logOnce(`${message.type} ${message.dropId}: balance ${message.balance}, expected ${expected / 1000}`)
    }
    balance = message.balance
  }

  function error (message) {
    if (message.code === 'E_WRONG_NODE' && !joinedAt && redirects < MAX_REDIRECTS && ownerSocketUrl(message.owner) !== null) return moveTo(ownerSocketUrl(message.owner))
    metrics.errors.add(1, { code: message.code })
    logOnce(`error ${message.code}: ${message.message}`)
    // A refused drop is never debited or announced.
    if (message.ref !== undefined) pending.delete(message.ref)
  }

  /** Leaves this socket quietly (nothing was dropped on it yet) and plays on from the room's owner. */
  function moveTo (ownerUrl) {
    finished = true
    closedByUs = true
    clearTimeout(joinTimer)
    metrics.redirects.add(1)
    ws.close(1000)
    connect(config, room, token, leaveAt, ownerUrl, redirects + 1)
  }

  /**
   * Called on frame `every`·k (remember it) and the one after (time the pair).
   * The tick is the uint32 LE at offset 1 of the snapshot, which a room frame
   * (kind 2: uint32 events length L at offset 1, then L bytes of events)
   * carries at offset 5 + L.
   */
  function sampleSnapshot (buffer, at) {
    const head = new Uint8Array(buffer, 0, 5)
    const start = head[0] === 2 ? 5 + (head[1] | (head[2] << 8) | (head[3] << 16)) + head[4] * 16777216 : 0
    const b = new Uint8Array(buffer, start + 1, 4)
    const tick = (b[0] | (b[1] << 8) | (b[2] << 16)) + b[3] * 16777216
    if (sampleTick >= 0) {
      const ticks = tick - sampleTick
      if (ticks > 0) {
        const elapsed = at - sampleAt
        if (ticks === snapshotEvery) metrics.snapshotInterval.add(elapsed)
        metrics.snapshotJitter.add(Math.abs(elapsed - ticks * TICK_MS))
      }
      sampleTick = -1
      phase = 0
    } else {
      sampleTick = tick
      sampleAt = at
    }
  }

  /**
   * Seeds mode: a drop-events frame (protocol/drop-events-codec.js: kind 3,
   * N at offset 13, 15 + 64·N bytes); its events are counted, not decoded
   * (k6's CPU is shared with the server). Anything else is an error.
   */
  function dropEvents (buffer) {
    const bytes = new Uint8Array(buffer)
    if (bytes[0] !== 3) {
      metrics.errors.add(1, { code: 'X_UNEXPECTED_SNAPSHOT' })
      return logOnce(`binary frame of kind ${bytes[0]} on a seeds socket`)
    }
    const count = bytes.length >= 15 ? bytes[13] | (bytes[14] << 8) : -1
    if (count < 0 || bytes.length !== 15 + 64 * count) {
      metrics.errors.add(1, { code: 'X_BAD_FRAME' })
      return logOnce(`drop-events frame of ${bytes.length} bytes`)
    }
    dropEventCount += count
  }

  /** Stops dropping, waits for the last settles (at most DRAIN), then closes. */
  function leave () {
    if (leaving || finished) return
    leaving = true
    if (dropTimer !== null) clearInterval(dropTimer)
    const deadline = Date.now() + config.drainS * 1000
    const poll = setInterval(() => {
      if (finished || (pending.size === 0 && inFlight.size === 0) || Date.now() >= deadline) {
        clearInterval(poll)
        close()
      }
    }, DRAIN_POLL_MS)
  }

  function close () {
    if (finished) return
    closedByUs = true
    ws.close(1000)
  }

  function closed (code) {
    if (finished) return
    finished = true
    leaving = true
    clearTimeout(joinTimer)
    if (dropTimer !== null) clearInterval(dropTimer)
    if (!closedByUs) {
      metrics.errors.add(1, { code: `WS_CLOSE_${code}` })
      logOnce(`server closed the connection: ${code}`)
    }
    const unsettled = pending.size + inFlight.size
    metrics.unsettledDrops.add(unsettled)
    if (unsettled > 0) logOnce(`${unsettled} drops unsettled when leaving`)
    metrics.errors.add(0)
    metrics.balanceMismatches.add(0)
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
}

/** Credits (up to three decimals, as the server sends them) in milli-credits, for exact sums. */
function milli (credits) {
  return Math.round(credits * 1000)
}
