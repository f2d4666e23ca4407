import { ENGINE_VERSION, isEngineVersion } from '/engine/index.js'
import { byId, el, formatAmount, shortHex } from './dom.js'
import { Session } from './session.js'
import { GameSocket, CLOSE_UNAUTHORIZED } from './game-socket.js'
import { decodeSnapshot, splitRoomFrame } from '/protocol/snapshot-codec.js'
import { parseRoomId, roomIdOf, ROWS, RISKS } from '/protocol/room-id.js'
import { socketUrl } from './socket-url.js'
import { SnapshotTimeline } from './snapshot-timeline.js'
import { RoomView } from './room-view.js'
import { DropVerifier } from './drop-verifier.js'
import { BoardRenderer } from './board-renderer.js'
import { HistoryView } from './history-view.js'
import { FairnessPanel } from './fairness-panel.js'

/**
 * The player's page: connects with the guest session, joins the chosen
 * room, renders every ball in it from the snapshots, and verifies every
 * drop against its own simulation. State for tests is on window.__plinko.
 */

const ROOM_KEY = 'plinko.room'
const BET_KEY = 'plinko.bet'
const AUTO_DROP_EVERY_MS = 250
/** E_WRONG_NODE redirects followed in a row without a join; past this the page stops and says so. */
const MAX_REDIRECTS = 3

const session = new Session()
const verifier = new DropVerifier()
const renderer = new BoardRenderer(byId('board'))
const history = new HistoryView(byId('history'), (dropId) => fairness.verifyDrop(dropId).then(() => byId('fairness').scrollIntoView({ behavior: 'smooth' })))
const fairness = new FairnessPanel({ session, onRotated: () => loadHistory(), say })
const snapshotChecks = { positions: 0, mismatches: 0, unknown: 0 }

const state = {
  playerId: null,
  balance: null,
  minBet: 1,
  maxBet: Infinity,
  roomId: initialRoom(),
  /** @type {string | null} the room the server says we are in */
  joinedRoom: null,
  /** Where the socket connects: this page's directory, or the process E_WRONG_NODE named. */
  socketBase: new URL('.', location.href).href,
  redirects: 0,
  /** @type {RoomView | null} */
  view: null,
  /** @type {SnapshotTimeline | null} */
  timeline: null,
  refs: 0,
  auto: { remaining: 0, timer: null },
  status: 'connecting',
  warnings: [],
  /** @type {{ now: number, tick: number, balls: number, deviation: number, a: number | null, b: number | null }[] | null} per-frame record, when tracing */
  trace: null
}

const socket = new GameSocket({
  url: () => socketUrl(state.socketBase, session.token ?? ''),
  onMessage: handleMessage,
  onBinary: handleSnapshot,
  onStatus: showStatus,
  onClose (code) {
    state.joinedRoom = null
    if (code !== CLOSE_UNAUTHORIZED) return true
    // The server no longer knows this session (a new database): start a new one.
    session.renew().then(() => {
      history.clear()
      loadHistory()
      socket.start()
    }, (error) => say(`Could not start a new session: ${error.message}`, 'error'))
    return false
  }
})

// ---- messages -------------------------------------------------------------

function handleMessage (message) {
  switch (message.type) {
    case 'welcome': return onWelcome(message)
    case 'joined': return onJoined(message)
    case 'dropped': return onDropped(message)
    case 'settled': return onSettled(message)
    case 'error': return onError(message)
    case 'balance': return setBalance(message.balance)
    case 'events': return handleRoomEvents(message.events)
  }
}

function onWelcome (message) {
  state.playerId = message.playerId
  state.minBet = message.minBet
  state.maxBet = message.maxBet
  setBalance(message.balance)
  fairness.update({ serverSeedHash: message.serverSeedHash, clientSeed: message.clientSeed, nonce: message.nonce })
  byId('bet').min = String(message.minBet)
  byId('bet').max = String(message.maxBet)
  if (!isEngineVersion(message.engineVersion)) {
    warn(`The server runs engine ${message.engineVersion}, which this page's engine (up to ${ENGINE_VERSION}) does not have: reload the page. Drops cannot be verified until then.`)
  }
  join(state.roomId)
  if (socket.connects > 1) reconcile()
}

function onJoined (message) {
  state.redirects = 0
  const parsed = parseRoomId(message.room)
  const board = verifier.board(parsed.rows, parsed.risk, message.engineVersion)
  if (!sameBoard(board, message.board)) {
    warn(`The server's board for room ${message.room} differs from the one this page's engine builds: outcomes shown here may not match.`)
  }
  state.joinedRoom = message.room
  state.view = new RoomView({ room: message.room, board, snapshotChecks })
  state.timeline = new SnapshotTimeline({ tickRate: message.tickRate, snapshotEvery: message.snapshotEvery })
  state.timeline.observe(message.tick, performance.now())
  renderer.setBoard(board)
  const inRoom = new Set()
  for (const ball of message.balls) {
    inRoom.add(ball.dropId)
    track({ ...ball, room: message.room })
  }
  // Other players' drops that were announced before and are not here any more: their settlements will not reach us.
  verifier.forget((local) => !local.mine && !inRoom.has(local.dropId))
  say(`Joined room ${message.room}.`)
}

function onDropped (message) {
  const mine = message.player === state.playerId
  if (message.room === state.joinedRoom || mine) track(message)
  if (!mine) return
  setBalance(message.balance)
  fairness.update({ nonce: message.nonce + 1 })
  const committed = fairness.state.serverSeedHash
  if (committed && message.serverSeedHash !== committed) {
    warn(`Drop #${message.dropId} was made with server seed hash ${shortHex(message.serverSeedHash)}, not the committed ${shortHex(committed)}.`)
  }
  history.upsert(message.dropId, { room: message.room, bet: message.bet })
}

function onSettled (message) {
  const verification = verifier.settle(message)
  if (verification && !verification.verified) warnMismatch(verification)
  if (message.player !== state.playerId) return
  setBalance(message.balance)
  history.upsert(message.dropId, {
    room: message.room,
    bet: message.bet,
    multiplier: message.multiplier,
    payout: message.payout,
    verified: verification ? verification.verified : null
  })
  updateSummary()
}

function onError (message) {
  if (message.code === 'E_WRONG_NODE') return followRedirect(message)
  say(`${message.code}: ${message.message}`, 'error')
  if (typeof message.ref !== 'string' || !message.ref.startsWith('auto-') || state.auto.timer === null) return
  // A refused auto-drop: try that ball again later, or stop when retrying cannot help.
  if (message.code === 'E_RATE_LIMITED' || message.code === 'E_ROOM_FULL') {
    state.auto.remaining++
    renderAutoButton()
  } else {
    stopAuto()
  }
}

function handleSnapshot (frame, receivedAt) {
  const split = splitRoomFrame(frame)
  if (!split) return
  handleRoomEvents(split.events)
  const snapshot = decodeSnapshot(split.snapshot)
  if (!snapshot || !state.view || !state.timeline) return
  state.view.check(snapshot)
  state.timeline.push(snapshot, receivedAt)
}

/**
 * The other players' `dropped`/`settled` of a snapshot period (in a room
 * frame, or an `events` message), handled as if each had come on its own.
 * Our own are skipped: they come on their own at once, with the balance.
 */
function handleRoomEvents (events) {
  for (const event of events) {
    if (event.player !== state.playerId && (event.type === 'dropped' || event.type === 'settled')) handleMessage(event)
  }
}

/** Simulates an announced drop and, if it is in this room, shows its ball. */
function track (announced) {
  const parsed = parseRoomId(announced.room)
  if (!parsed) return
  const local = verifier.simulate(announced, parsed, state.playerId)
  if (announced.room === state.joinedRoom && state.view) state.view.add(local)
}

/** After a reconnect: settle from the ledger what settled while we were away. */
async function reconcile () {
  await loadHistory()
  updateSummary()
}

/**
 * Clustered, the room runs on another process: reconnect there (the
 * `welcome` handler joins the room again). Bounded, so two processes that
 * disagree cannot bounce the page for ever.
 */
function followRedirect (message) {
  if (message.room !== state.roomId) return
  if (state.redirects >= MAX_REDIRECTS || socketUrl(message.owner, '') === null) {
    say(`Room ${message.room} runs on ${message.owner}, which this page could not join: reload to try again.`, 'error')
    return
  }
  state.redirects++
  state.socketBase = message.owner
  state.joinedRoom = null
  say(`Room ${message.room} runs on another server; moving there…`)
  socket.reconnectNow()
}

// ---- actions ------------------------------------------------------------

function join (roomId) {
  state.roomId = roomId
  localStorage.setItem(ROOM_KEY, roomId)
  socket.send({ type: 'join', room: roomId, ref: 'join' })
}

/** @param {string} [ref] */
function drop (ref = `drop-${++state.refs}`) {
  const bet = Number(byId('bet').value)
  if (!Number.isSafeInteger(bet) || bet < state.minBet || bet > state.maxBet) {
    say(`The bet must be a whole number from ${state.minBet} to ${formatAmount(state.maxBet)}.`, 'error')
    return false
  }
  if (state.balance !== null && bet > state.balance) {
    say('Not enough balance for this bet.', 'error')
    return false
  }
  if (!state.joinedRoom || !socket.send({ type: 'drop', bet, ref })) {
    say('Not connected: the drop was not sent.', 'error')
    return false
  }
  localStorage.setItem(BET_KEY, String(bet))
  return true
}

function startAuto () {
  const count = Number(byId('auto-count').value)
  if (!Number.isSafeInteger(count) || count < 1) {
    say('Auto-drop needs a number of balls.', 'error')
    return
  }
  state.auto.remaining = count
  const tickAuto = () => {
    if (state.auto.remaining <= 0) return stopAuto()
    if (drop(`auto-${++state.refs}`)) state.auto.remaining--
    else return stopAuto()
    renderAutoButton()
  }
  state.auto.timer = setInterval(tickAuto, AUTO_DROP_EVERY_MS)
  tickAuto()
}

function stopAuto () {
  clearInterval(state.auto.timer)
  state.auto.timer = null
  state.auto.remaining = 0
  renderAutoButton()
}

function renderAutoButton () {
  const button = byId('auto')
  const running = state.auto.timer !== null
  button.textContent = running ? `Stop (${state.auto.remaining})` : 'Auto'
  button.classList.toggle('running', running)
}

async function loadHistory () {
  if (!session.token) return
  try {
    const { drops } = await session.request('GET', '/api/drops?limit=50')
    for (const record of drops.slice().reverse()) {
      const verification = verifier.settleFromRecord(record)
      if (verification && !verification.verified) warnMismatch(verification)
      history.upsert(record.id, {
        room: record.room,
        bet: record.bet,
        multiplier: record.multiplier,
        payout: record.payout,
        verified: verification ? verification.verified : null,
        revealed: Boolean(record.serverSeed)
      })
    }
    updateSummary()
  } catch (error) {
    say(`Could not load your drops: ${error.message}`, 'error')
  }
}

// ---- view ---------------------------------------------------------------

function setBalance (balance) {
  state.balance = balance
  byId('balance').textContent = formatAmount(balance)
}

function say (text, kind = 'info') {
  const line = byId('message')
  line.textContent = text
  line.dataset.kind = kind
}

function warn (text) {
  state.warnings.push(text)
  const box = byId('alert')
  box.hidden = false
  box.append(el('p', { text: `⚠ ${text}` }))
}

function warnMismatch (v) {
  warn(`Drop #${v.dropId} did NOT verify: this browser computed bucket ${v.localBucket} after ${v.localTicks} ticks (state ${v.localStateHash}), the server says bucket ${v.serverBucket} after ${v.serverTicks} ticks (state ${v.serverStateHash}).`)
}

function updateSummary () {
  const total = verifier.total
  const failed = verifier.failures
  const summary = byId('verify-summary')
  summary.className = failed > 0 ? 'summary bad' : 'summary ok'
  summary.textContent = total === 0
    ? 'Every drop is simulated in your browser and checked against the server.'
    : failed === 0
      ? `✓ ${total} drop${total === 1 ? '' : 's'} verified in this browser`
      : `⚠ ${failed} of ${total} drops did NOT verify`
}

function showStatus (status, detail) {
  state.status = status
  const pill = byId('connection')
  pill.dataset.status = status
  pill.textContent = status === 'open'
    ? 'online'
    : status === 'waiting'
      ? `reconnecting in ${(detail.retryInMs / 1000).toFixed(1)} s`
      : status === 'connecting' ? (detail.attempt > 0 ? 'reconnecting…' : 'connecting…') : 'offline'
}

function updateFooter () {
  const t = state.timeline
  const parts = [`engine ${ENGINE_VERSION}`]
  if (socket.rttMs !== null) parts.push(`rtt ${Math.round(socket.rttMs)} ms`)
  if (t) parts.push(`buffer ${Math.round(t.delayMs)} ms (jitter ${Math.round(t.jitterMs)} ms)`)
  parts.push(`snapshot positions checked ${snapshotChecks.positions}${snapshotChecks.mismatches ? `, ${snapshotChecks.mismatches} OFF` : ''}`)
  byId('footer-stats').textContent = parts.join(' · ')
}

let idleDrawn = false
function frame (now) {
  requestAnimationFrame(frame)
  const { view, timeline } = state
  let poses = []
  if (view && timeline) {
    const tick = timeline.advance(now)
    if (tick !== null) {
      const { a, b } = timeline.bracket(tick)
      poses = view.posesAt(tick, a, b)
      if (state.trace && poses.length > 0 && state.trace.length < 20_000) {
        let deviation = 0
        for (const pose of poses) deviation = Math.max(deviation, pose.deviation)
        state.trace.push({ now, tick, balls: poses.length, deviation, a: a ? a.tick : null, b: b ? b.tick : null })
      }
    }
    for (const landing of view.landings) renderer.flash(landing.bucket, landing.mine, now)
    view.landings.length = 0
  }
  // Nothing moves: keep the last frame.
  if (poses.length === 0 && renderer.flashes.length === 0 && !renderer.needsDraw) {
    if (idleDrawn) return
    idleDrawn = true
  } else {
    idleDrawn = false
  }
  renderer.draw(poses, now)
}

// ---- set-up -------------------------------------------------------------

function initialRoom () {
  const stored = localStorage.getItem(ROOM_KEY)
  return parseRoomId(stored) ? stored : roomIdOf(16, 'medium')
}

function sameBoard (local, remote) {
  return remote && local.width === remote.width && local.height === remote.height &&
    JSON.stringify(local.pegs) === JSON.stringify(remote.pegs) &&
    JSON.stringify(local.walls) === JSON.stringify(remote.walls) &&
    JSON.stringify(local.multipliers) === JSON.stringify(remote.multipliers)
}

function setUpControls () {
  const { rows, risk } = parseRoomId(state.roomId)
  const rowsSelect = byId('rows')
  const riskSelect = byId('risk')
  for (const r of ROWS) rowsSelect.append(el('option', { value: String(r), text: String(r), selected: r === rows }))
  for (const k of RISKS) riskSelect.append(el('option', { value: k, text: k, selected: k === risk }))
  const onRoom = () => join(roomIdOf(Number(rowsSelect.value), riskSelect.value))
  rowsSelect.addEventListener('change', onRoom)
  riskSelect.addEventListener('change', onRoom)

  const bet = byId('bet')
  bet.value = localStorage.getItem(BET_KEY) ?? '10'
  for (const button of document.querySelectorAll('[data-bet]')) {
    button.addEventListener('click', () => {
      const value = Number(bet.value) || state.minBet
      const next = button.dataset.bet === 'half' ? Math.floor(value / 2) : value * 2
      bet.value = String(Math.max(state.minBet, Math.min(state.maxBet, next)))
    })
  }
  byId('drop').addEventListener('click', () => drop())
  byId('board').addEventListener('click', () => drop())
  byId('auto').addEventListener('click', () => (state.auto.timer ? stopAuto() : startAuto()))

  document.addEventListener('keydown', (event) => {
    if (event.code !== 'Space' || isTyping(event.target)) return
    event.preventDefault()
    if (!event.repeat) drop()
  })
  // Space on a focused button would click it as well: the keydown above already dropped.
  document.addEventListener('keyup', (event) => {
    if (event.code === 'Space' && !isTyping(event.target)) event.preventDefault()
  })
}

function isTyping (target) {
  return target instanceof HTMLElement && (target.isContentEditable || ['INPUT', 'TEXTAREA', 'SELECT'].includes(target.tagName))
}

/** What tests (and curious players) can read. */
window.__plinko = {
  get ready () { return state.joinedRoom !== null },
  get playerId () { return state.playerId },
  get balance () { return state.balance },
  get room () { return state.joinedRoom },
  get status () { return state.status },
  get connects () { return socket.connects },
  /** where the socket connects (changes after an E_WRONG_NODE redirect) */
  get socketBase () { return state.socketBase },
  get verifications () { return verifier.results.map((v) => ({ ...v })) },
  get pendingVerifications () { return verifier.pending.size },
  get history () { return history.entries },
  get fairnessChecks () { return fairness.checks.map((c) => ({ ...c })) },
  get lastReveal () { return fairness.lastReveal },
  get snapshotChecks () { return { ...snapshotChecks } },
  get timeline () { return state.timeline ? { ...state.timeline.stats, delayMs: state.timeline.delayMs, jitterMs: state.timeline.jitterMs, ticksPerSecond: state.timeline.rate * 1000 } : null },
  get frames () { return renderer.frames },
  get warnings () { return state.warnings.slice() },
  engineVersion: ENGINE_VERSION,
  drop: () => drop(),
  join: (roomId) => join(roomId),
  dropConnection: () => socket.drop(),
  /** Starts recording every rendered frame (render tick, balls, largest distance from the simulated path). */
  startTrace: () => { state.trace = [] },
  get trace () { return state.trace }
}

function main () {
  setUpControls()
  renderAutoButton()
  updateSummary()
  requestAnimationFrame(frame)
  setInterval(updateFooter, 1000)
  connect()
}

/** Opens the session (retrying while the server is unreachable), then the socket. */
async function connect () {
  try {
    const me = await session.open()
    state.playerId = me.playerId
    setBalance(me.balance)
    fairness.update(me)
  } catch (error) {
    say(`Cannot reach the server (${error.message}); retrying…`, 'error')
    setTimeout(connect, 3000)
    return
  }
  await loadHistory()
  socket.start()
}

main()
