import { ENGINE_VERSION, isEngineVersion } from '/engine/index.js'
import { apiRequest } from './api.js'
import { byId, el, formatAmount, formatSigned, shortHex, showAmount } from './dom.js'
import { Session } from './session.js'
import { GameSocket, CLOSE_UNAUTHORIZED } from './game-socket.js'
import { decodeSnapshot, splitRoomFrame } from '/protocol/snapshot-codec.js'
import { parseRoomId, roomIdOf, ROWS, RISKS } from '/protocol/room-id.js'
import { socketUrl } from './socket-url.js'
import { SnapshotTimeline } from './snapshot-timeline.js'
import { RoomView } from './room-view.js'
import { DropVerifier } from './drop-verifier.js'
import { BoardRenderer, bucketColors, bucketTextColors } from './board-renderer.js'
import { HistoryView } from './history-view.js'
import { FairnessPanel } from './fairness-panel.js'
import { pegRowCount } from './peg-contacts.js'
import { Sound } from './sound.js'
import { AutoBet, clampBet, STOP_RULE } from './auto-bet.js'
import { SessionStats } from './session-stats.js'
import { LiveFeed, BIG_WIN } from './live-feed.js'
import { ResultsStrip } from './results-strip.js'
import { RecallView } from './recall-view.js'
import { SeededRoom } from './seeded-room.js'
import { RoomClock } from './room-clock.js'
import { pageDelivery, applyDropEvents, reportDesync, DELIVERY_SNAPSHOTS } from './seeds-delivery.js'
import { SessionHistory } from './session-history.js'
import { Announcer } from './announcer.js'

/**
 * The player's page: connects with the guest session, joins the chosen
 * room, renders every ball in it from the snapshots, and verifies every
 * drop against its own simulation. Everything the board shows happening —
 * peg glows and ticks, bucket bounces, payouts, big-win bursts — comes
 * from that simulation, at the moment the render clock reaches it; a
 * drop's result (the strip, the feed, the session stats, the floating
 * payout) is revealed once its ball has landed on screen and the server
 * has settled it. State for tests is on window.__plinko.
 */

const ROOM_KEY = 'plinko.room'
const BET_KEY = 'plinko.bet'
const AUTO_DROP_EVERY_MS = 250
/** E_WRONG_NODE redirects followed in a row without a join; past this the page stops and says so. */
const MAX_REDIRECTS = 3
/** A floating "+payout" for own wins of this multiple or more (BIG_WIN and up: the big celebration). */
const FLOAT_WIN = 2
/** A result that comes this soon after its ball landed on screen still gets its effects (seeds mode draws close to the room's tick). */
const LATE_RESULT_MS = 1000
/** How often the room's player count is asked for (GET /api/rooms). */
const PLAYERS_EVERY_MS = 4000
/** Drops in the history table (GET /api/drops?limit=). */
const HISTORY_LIMIT = 50

const session = new Session()
const verifier = new DropVerifier()
const renderer = new BoardRenderer(byId('board'), { maxHeight: boardMaxHeight })
const history = new HistoryView(byId('history'),
  (dropId) => fairness.verifyDrop(dropId).then(() => byId('fairness').scrollIntoView({ behavior: renderer.reducedMotion ? 'auto' : 'smooth' })),
  (dropId) => recall.open(dropId))
const fairness = new FairnessPanel({ session, onRotated: () => loadHistory(), say })
const recall = new RecallView({ session, verifier })
const sound = new Sound()
const stats = new SessionStats({ wagered: byId('stat-wagered'), profit: byId('stat-profit'), drops: byId('stat-drops'), best: byId('stat-best'), chart: byId('profit-chart') })
const feed = new LiveFeed(byId('feed'))
const recent = new ResultsStrip(byId('recent'))
const sessionHistory = new SessionHistory(session)
const announcer = new Announcer(byId('announcer'))
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
  /** @type {AutoBet | null} the running (or last) auto-bet run */
  autoRun: null,
  autoTimer: null,
  /** @type {Map<number, any>} own `settled` messages whose ball has not landed on screen yet */
  settledUnseen: new Map(),
  /** @type {Set<number>} own drops announced to this page (results revealed once each) */
  ownDrops: new Set(),
  revealed: new Set(),
  feedRoom: null,
  players: null,
  playersTimer: null,
  /** balls drawn in the last frame: all, and those no announcement explains */
  lastFrame: { balls: 0, unknown: 0, mine: 0 },
  /** performance.now() of the first frame with the board drawn */
  firstBoardFrameAt: null,
  status: 'connecting',
  warnings: [],
  /** The delivery mode asked for in `join` (seeds-delivery.js), and the rooms switched to snapshots after a desync. */
  delivery: pageDelivery(location.search),
  snapshotRooms: new Set(),
  /** Seeds mode: binary frames that were not drop events, and the desyncs seen. */
  seeds: { otherFrames: 0, desyncs: [] },
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
    if (state.autoRun?.running) stopAuto('disconnected')
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
  if (message.delivery === 'seeds') {
    // The page simulates the room itself (seeded-room.js) at the room's tick.
    state.view = new SeededRoom({ room: message.room, board, boardFor: (engineVersion) => verifier.board(parsed.rows, parsed.risk, engineVersion) })
    state.timeline = new RoomClock({ tickRate: message.tickRate, rttMs: () => socket.rttMs })
  } else {
    state.view = new RoomView({ room: message.room, board, snapshotChecks, snapshotEvery: message.snapshotEvery })
    state.timeline = new SnapshotTimeline({ tickRate: message.tickRate, snapshotEvery: message.snapshotEvery })
  }
  state.timeline.observe(message.tick, performance.now())
  renderer.setBoard(board)
  const inRoom = new Set()
  for (const ball of message.balls) {
    inRoom.add(ball.dropId)
    track({ ...ball, room: message.room })
  }
  // Other players' drops that were announced before and are not here any more: their settlements will not reach us.
  verifier.forget((local) => !local.mine && !inRoom.has(local.dropId))
  // Own results waiting for a landing this new view will not show: reveal them now.
  for (const [dropId, settled] of state.settledUnseen) if (!state.view.drops.has(dropId)) reveal(settled, false)
  if (state.feedRoom !== message.room) feed.clear()
  state.feedRoom = message.room
  byId('room-name').textContent = message.room
  refreshPlayers()
  say(`Joined room ${message.room}.`)
  if (state.autoRun && state.autoRun.stopReason === 'disconnected') showAutoStatus()
}

function onDropped (message) {
  const mine = message.player === state.playerId
  if (message.room === state.joinedRoom || mine) track(message)
  if (!mine) return
  setBalance(message.balance)
  state.ownDrops.add(message.dropId)
  if (typeof message.ref === 'string' && state.autoRun?.refs.has(message.ref)) state.autoRun.dropIds.add(message.dropId)
  fairness.update({ nonce: message.nonce + 1 })
  const committed = fairness.state.serverSeedHash
  if (committed && message.serverSeedHash !== committed) {
    warn(`Drop #${message.dropId} was made with server seed hash ${shortHex(message.serverSeedHash)}, not the committed ${shortHex(committed)}.`)
  }
  history.upsert(message.dropId, { room: message.room, bet: message.bet })
}

function onSettled (message) {
  // Seeds mode: the ball's simulation may not have reached its landing yet.
  if (message.room === state.joinedRoom) state.view?.complete?.(message.dropId)
  const verification = verifier.settle(message)
  if (verification && !verification.verified) warnMismatch(verification)
  const local = message.room === state.joinedRoom ? state.view?.drops.get(message.dropId) : undefined
  if (message.room === state.joinedRoom) {
    // Shown in the feed when its ball lands on screen (or now, if it is not on this board).
    if (local && !local.landingShown) local.settled = message
    else addToFeed(message)
  }
  if (message.player !== state.playerId) return
  setBalance(message.balance)
  onAutoResult(message)
  if (local && !local.landingShown) state.settledUnseen.set(message.dropId, message)
  else reveal(message, local?.landedOnScreenAt !== undefined && performance.now() - local.landedOnScreenAt < LATE_RESULT_MS)
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
  if (message.ref === 'join' && state.delivery !== DELIVERY_SNAPSHOTS && (message.code === 'E_BAD_DELIVERY' || message.code === 'E_BAD_MESSAGE')) {
    // A server without the seeds delivery: snapshots it is.
    state.delivery = DELIVERY_SNAPSHOTS
    return join(state.roomId)
  }
  say(`${message.code}: ${message.message}`, 'error')
  const run = state.autoRun
  if (typeof message.ref !== 'string' || !run || !run.refs.has(message.ref)) return
  // A refused auto-drop: try that ball again later, or stop when retrying cannot help.
  if (run.running && (message.code === 'E_RATE_LIMITED' || message.code === 'E_ROOM_FULL' || message.code === 'E_SEED_ROTATING')) {
    run.retry(message.ref)
    renderAutoButton()
  } else {
    stopAuto(message.code === 'E_INSUFFICIENT_FUNDS' ? 'balance' : 'refused', message.code)
  }
}

// ---- results: revealed when the ball has landed on screen and the server settled it

/**
 * One of the player's results, shown everywhere at once: the strip above
 * the board, the session stats and (for a win of FLOAT_WIN× or more) the
 * floating payout; BIG_WIN× and more get the celebration.
 * @param {any} settled @param {boolean} live the ball just landed on screen (else: effects skipped)
 */
function reveal (settled, live) {
  if (state.revealed.has(settled.dropId) || !state.ownDrops.has(settled.dropId)) return
  state.settledUnseen.delete(settled.dropId)
  showResult(settled, state.view?.drops.get(settled.dropId)?.engineVersion, true)
  announcer.result(settled)
  if (!live || settled.room !== state.joinedRoom) return
  const now = performance.now()
  if (settled.multiplier >= FLOAT_WIN) renderer.floatText(settled.bucket, `+${formatAmount(settled.payout)}`, now, { big: settled.multiplier >= BIG_WIN })
  if (settled.multiplier >= BIG_WIN) renderer.celebrate(settled.bucket, now)
}

/**
 * A result into the strip and (`counted`) the session stats, once.
 * @param {{ dropId: number, room: string, bet: number, payout: number, multiplier: number, bucket: number }} settled
 * @param {string} [engineVersion] @param {boolean} counted
 */
function showResult (settled, engineVersion, counted) {
  state.revealed.add(settled.dropId)
  const parsed = parseRoomId(settled.room)
  const board = parsed ? verifier.board(parsed.rows, parsed.risk, engineVersion) : null
  const colors = board ? bucketColors(board.multipliers) : []
  const textColors = board ? bucketTextColors(board.multipliers) : []
  recent.add({ dropId: settled.dropId, multiplier: settled.multiplier, bucket: settled.bucket, color: colors[settled.bucket] ?? '#98a3cf', textColor: textColors[settled.bucket] })
  if (counted) stats.add({ bet: settled.bet, payout: settled.payout, multiplier: settled.multiplier })
}

/**
 * After a reload: this tab session's results back into the strip and the
 * session stats, from the server's history; its drops still falling are
 * the page's own again, so their results show when they settle.
 */
async function restoreSession (playerId, firstPage) {
  try {
    const { drops, statsAfter } = await sessionHistory.load(playerId, await firstPage)
    for (const record of drops) {
      if (state.revealed.has(record.id)) continue
      if (record.status !== 'settled') { state.ownDrops.add(record.id); continue }
      showResult({ dropId: record.id, room: record.room, bet: record.bet, payout: record.payout, multiplier: record.multiplier, bucket: record.bucket }, record.engineVersion, record.id > statsAfter)
    }
  } catch (error) {
    say(`Could not load this session's results: ${error.message}`, 'error')
  }
}

function resetSession () {
  stats.reset()
  let newest = 0
  for (const id of state.revealed) newest = Math.max(newest, id)
  sessionHistory.resetStats(newest)
}

function addToFeed (settled) {
  feed.add({ dropId: settled.dropId, player: settled.player, mine: settled.player === state.playerId, bet: settled.bet, multiplier: settled.multiplier, payout: settled.payout })
}

/** The room's player count (GET /api/rooms), refreshed while in the room. */
async function refreshPlayers () {
  clearTimeout(state.playersTimer)
  const room = state.joinedRoom
  if (!room) return
  try {
    const { rooms } = await apiRequest('GET', '/api/rooms')
    const here = rooms.find((r) => r.id === room)
    if (room === state.joinedRoom) {
      state.players = here ? here.players : null
      byId('room-players').textContent = state.players === null ? '– players' : `${state.players} player${state.players === 1 ? '' : 's'}`
    }
  } catch {}
  if (room === state.joinedRoom) state.playersTimer = setTimeout(refreshPlayers, PLAYERS_EVERY_MS)
}

function handleSnapshot (frame, receivedAt) {
  if (state.view instanceof SeededRoom) return onDropEvents(frame, receivedAt)
  const split = splitRoomFrame(frame)
  if (!split) return
  handleRoomEvents(split.events)
  const snapshot = decodeSnapshot(split.snapshot)
  if (!snapshot || !state.view || !state.timeline) return
  state.view.check(snapshot)
  state.timeline.push(snapshot, receivedAt)
}

/** Seeds mode: other players' drops go on the board, and the page's simulation is checked against the server's hash. */
function onDropEvents (frame, receivedAt) {
  const room = state.joinedRoom
  const check = applyDropEvents(frame, receivedAt, { view: state.view, clock: state.timeline, add: (event) => track({ ...event, room }) })
  if (check === null) { state.seeds.otherFrames++; return }
  if (check.ok) return
  const desync = { room, tick: check.tick, server: check.server, local: check.local, ballsInFlight: check.balls, engineVersion: state.view.board.engineVersion }
  state.seeds.desyncs.push(desync)
  say(`This page's simulation of room ${room} disagrees with the server's at tick ${check.tick}: showing the server's positions instead.`, 'error')
  state.snapshotRooms.add(room)
  join(room)
  reportDesync(desync, session.token).then((sent) => { desync.reported = sent })
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
  const live = announced.room === state.joinedRoom && state.view instanceof SeededRoom
  // Seeds mode: the ball's own simulation on the board gives the outcome the verifier checks.
  const local = live ? verifier.expect(announced, parsed, state.playerId) : verifier.simulate(announced, parsed, state.playerId)
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
  const delivery = state.snapshotRooms.has(roomId) ? DELIVERY_SNAPSHOTS : state.delivery
  socket.send({ type: 'join', room: roomId, delivery, ref: 'join' })
}

/**
 * A board change from the controls: refused (the selects put back) while
 * the player's own balls are still falling or an auto-bet runs, so no
 * ball of theirs ever vanishes from the board.
 */
function changeBoard (rows, risk) {
  const inFlight = state.view ? state.view.ownInFlight : 0
  const current = parseRoomId(state.roomId)
  const autoRunning = Boolean(state.autoRun?.running && state.autoTimer !== null)
  if (inFlight > 0 || autoRunning) {
    byId('rows').value = String(current.rows)
    byId('risk').value = current.risk
    say(autoRunning
      ? 'Stop the auto-bet before changing the board.'
      : `Wait for your ${inFlight} ball${inFlight === 1 ? '' : 's'} in flight to land before changing the board.`, 'error')
    return false
  }
  join(roomIdOf(rows, risk))
  return true
}

/** @param {string} [ref] @param {number} [betOverride] the auto-bet's bet */
function drop (ref = `drop-${++state.refs}`, betOverride) {
  const bet = betOverride ?? Number(byId('bet').value)
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
  if (betOverride === undefined) localStorage.setItem(BET_KEY, String(bet))
  return true
}

/** Reads the auto-bet form; undefined (and a message) when something is off. */
function autoRules () {
  const count = Number(byId('auto-count').value)
  const baseBet = Number(byId('bet').value)
  const optional = (id) => {
    const text = byId(id).value.trim()
    return text === '' || Number(text) === 0 ? null : Number(text)
  }
  const stopProfit = optional('auto-stop-profit')
  const stopLoss = optional('auto-stop-loss')
  const rule = (modeId, percentId) => ({ mode: byId(modeId).value === 'increase' ? 'increase' : 'reset', percent: Number(byId(percentId).value) || 0 })
  const guard = /** @type {HTMLInputElement} */ (byId('auto-guard')).checked
  const rules = { count, baseBet, stopProfit, stopLoss, guard, onWin: rule('auto-on-win', 'auto-win-percent'), onLoss: rule('auto-on-loss', 'auto-loss-percent') }
  if (!Number.isSafeInteger(count) || count < 1) return say('Auto-bet needs a number of bets (1 or more).', 'error')
  if (!Number.isSafeInteger(baseBet) || baseBet < state.minBet || baseBet > state.maxBet) return say(`The bet must be a whole number from ${state.minBet} to ${formatAmount(state.maxBet)}.`, 'error')
  for (const limit of [stopProfit, stopLoss]) if (limit !== null && !(limit > 0)) return say('Stop on profit and stop on loss are amounts above 0 (or empty: off).', 'error')
  for (const r of [rules.onWin, rules.onLoss]) if (!(r.percent >= 0 && r.percent <= 1000)) return say('Increase by 0 to 1000 %.', 'error')
  return rules
}

function startAuto () {
  const rules = autoRules()
  if (!rules) return
  if (!state.joinedRoom) return say('Not connected: auto-bet did not start.', 'error')
  state.autoRun = new AutoBet(rules, { minBet: state.minBet, maxBet: state.maxBet })
  runAuto()
}

/** Continues a run stopped by a lost connection, with the bets it had left. */
function resumeAuto () {
  const run = state.autoRun
  if (!run || run.stopReason !== 'disconnected' || run.remaining <= 0) return
  if (!state.joinedRoom) return say('Still not connected: the auto-bet can resume once the page is back in its room.', 'error')
  run.resume()
  say(`Auto-bet resumed: ${run.remaining} bets left.`)
  runAuto()
}

function runAuto () {
  const run = state.autoRun
  const tick = () => {
    if (!run.running) return stopAuto(run.stopReason)
    const bet = run.nextBet(state.balance)
    if (bet === null) return stopAuto('balance')
    const guard = run.guardBet(bet)
    if (guard === 'stop') return stopAuto('guard')
    if (guard === 'wait') return showAutoStatus()
    const ref = `auto-${++state.refs}`
    if (!drop(ref, bet)) return stopAuto(state.joinedRoom ? 'refused' : 'disconnected')
    run.markSent(ref, bet)
    renderAutoButton()
    if (!run.running) stopAuto(run.stopReason)
    else showAutoStatus()
  }
  clearInterval(state.autoTimer)
  state.autoTimer = setInterval(tick, AUTO_DROP_EVERY_MS)
  tick()
}

/** A settled drop of the auto-bet: its bet for the next drop, and its stop rules. */
function onAutoResult (settled) {
  const run = state.autoRun
  if (!run || !run.dropIds.has(settled.dropId)) return
  const stopped = run.result({ bet: settled.bet, payout: settled.payout, dropId: settled.dropId })
  if (stopped) stopAuto(stopped)
  else showAutoStatus()
}

/** @param {AutoBet['stopReason']} reason @param {string} [detail] */
function stopAuto (reason = 'stopped', detail) {
  clearInterval(state.autoTimer)
  state.autoTimer = null
  const run = state.autoRun
  if (run) {
    run.stop(reason)
    if (detail) run.detail = detail
  }
  renderAutoButton()
  showAutoStatus()
}

/** Why a run stopped sending, with where it stood then (`run.stoppedAt`). */
const AUTO_STOPS = {
  done: (run, at) => `Auto-bet sent all ${at.sent} bets.`,
  profit: (run, at) => `Auto-bet stopped sending at ${formatSigned(at.profit)}: the stop on profit of ${formatAmount(run.rules.stopProfit)} was reached.`,
  loss: (run, at) => `Auto-bet stopped sending at ${formatSigned(at.profit)}: the stop on loss of ${formatAmount(run.rules.stopLoss)} was reached.`,
  guard: (run, at) => `Auto-bet stopped sending at ${formatSigned(at.profit)}: the next bet of ${formatAmount(run.bet)} could take the loss past the stop on loss of ${formatAmount(run.rules.stopLoss)}.`,
  balance: (run, at) => `Auto-bet stopped after ${at.sent} bets: the balance does not cover the bet.`,
  disconnected: (run, at) => `Auto-bet stopped: the connection was lost after ${at.sent} of ${run.rules.count} bets.`,
  refused: (run, at) => `Auto-bet stopped after ${at.sent} bets: a drop was refused${run.detail ? ` (${run.detail})` : ''}.`,
  stopped: (run, at) => `Auto-bet stopped after ${at.sent} of ${run.rules.count} bets.`
}

/** The run's status: while sending, its progress; once stopped, why and where, then one final result once its last ball has landed. */
function autoStatusText (run) {
  if (run.running) return `Auto-bet: ${run.sent} of ${run.rules.count} sent, next bet ${formatAmount(run.bet)}, profit ${formatSigned(run.profit)}${run.inFlight > 0 ? ` (${run.inFlight} falling)` : ''}.`
  const why = AUTO_STOPS[run.stopReason](run, run.stoppedAt ?? { profit: run.profit, sent: run.sent, settled: run.settled })
  if (!run.finished) return `${why} ${run.inFlight} ball${run.inFlight === 1 ? '' : 's'} still falling: the final result follows when ${run.inFlight === 1 ? 'it lands' : 'they land'}.`
  const late = run.settled - (run.stoppedAt?.settled ?? run.settled)
  return `${why} Final result: ${formatSigned(run.profit)} over ${run.settled} bet${run.settled === 1 ? '' : 's'}${late > 0 ? `, counting the ${late} ball${late === 1 ? '' : 's'} still falling when it stopped` : ''}.`
}

function showAutoStatus () {
  const run = state.autoRun
  const box = byId('auto-status')
  if (!run) { box.hidden = true; return }
  box.hidden = false
  box.dataset.state = run.running ? 'running' : run.finished ? 'finished' : run.stopReason
  byId('auto-status-text').textContent = autoStatusText(run)
  if (run.finished && !run.announced) {
    run.announced = true
    announcer.say(autoStatusText(run))
  }
  const resumable = run.stopReason === 'disconnected' && run.remaining > 0
  const resume = byId('auto-resume')
  resume.hidden = !resumable
  resume.disabled = !state.joinedRoom
  resume.textContent = state.joinedRoom ? `Resume (${run.remaining} left)` : `Resume (${run.remaining} left) once reconnected`
}

function renderAutoButton () {
  const button = byId('auto')
  const run = state.autoRun
  const running = Boolean(run?.running && state.autoTimer !== null)
  button.replaceChildren(running ? `Stop (${run.remaining})` : 'Auto', ' ', el('kbd', { class: 'key-hint', text: 'A' }))
  button.classList.toggle('running', running)
}

function toggleAuto () {
  if (state.autoRun?.running && state.autoTimer !== null) stopAuto('stopped')
  else startAuto()
}

/** ½ and 2×: within MIN_BET, MAX_BET and the balance. @param {'half' | 'double'} how */
function changeBet (how) {
  const input = byId('bet')
  const value = Number(input.value) || state.minBet
  const next = how === 'half' ? Math.floor(value / 2) : value * 2
  const clamped = clampBet(next, { minBet: state.minBet, maxBet: state.maxBet }, state.balance)
  input.value = String(clamped ?? state.minBet)
  if (how === 'double' && clamped !== null && clamped < next) say(`The bet is capped at ${formatAmount(clamped)} (${clamped === state.maxBet ? 'the table limit' : 'your balance'}).`)
}

/** @param {Promise<{ drops: any[] }>} [page] the newest drops, if read already */
async function loadHistory (page) {
  if (!session.token) return
  try {
    const { drops } = await (page ?? session.request('GET', `/api/drops?limit=${HISTORY_LIMIT}`))
    for (const record of drops.slice().reverse()) {
      // Settled while this page was away (a reconnect): its result is final, and shown now.
      if (record.status === 'settled' && state.ownDrops.has(record.id) && !state.revealed.has(record.id) && !state.view?.drops.has(record.id)) {
        reveal({ dropId: record.id, room: record.room, bet: record.bet, multiplier: record.multiplier, payout: record.payout, bucket: record.bucket }, false)
        onAutoResult({ dropId: record.id, bet: record.bet, payout: record.payout })
      }
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
  showAmount(byId('balance'), balance)
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
  if (status !== 'open' && state.autoRun?.running) stopAuto('disconnected')
  if (state.autoRun) showAutoStatus()
  const pill = byId('connection')
  pill.dataset.status = status
  pill.title = status
  byId('connection-text').textContent = status === 'open'
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
    let mine = 0
    for (const pose of poses) if (pose.mine) mine++
    state.lastFrame = { balls: poses.length, unknown: view.unknownDrawn, mine }
    const rows = pegRowCount(view.board)
    for (const hit of view.pegHits) {
      renderer.glowPeg(hit.peg, hit.mine, now)
      sound.pegTick(hit.row, rows, hit.mine)
    }
    view.pegHits.length = 0
    for (const landing of view.landings) onLanding(landing, now)
    view.landings.length = 0
  }
  // Nothing moves: keep the last frame.
  if (poses.length === 0 && !renderer.busy && !renderer.needsDraw) {
    if (idleDrawn) return
    idleDrawn = true
  } else {
    idleDrawn = false
  }
  renderer.draw(poses, now)
  if (state.firstBoardFrameAt === null && renderer.frames > 0) state.firstBoardFrameAt = performance.now()
}

/** A ball reached its bucket on screen (the local simulation's landing). */
function onLanding (landing, now) {
  const drop = landing.drop
  const multiplier = state.view.board.multipliers[landing.bucket]
  if (!landing.stale) {
    drop.landedOnScreenAt = now
    renderer.flash(landing.bucket, landing.mine, now)
    sound.landing(multiplier, landing.mine)
  }
  if (drop.settled) addToFeed(drop.settled)
  else if (drop.result) addToFeed(drop.result) // seeds mode: another player's, as simulated here
  const settled = state.settledUnseen.get(landing.dropId)
  if (settled) reveal(settled, !landing.stale)
}

// ---- set-up -------------------------------------------------------------

/**
 * The tallest the board may be (CSS px), as the stylesheet's
 * --board-max-height: on a wide screen the window's height less the
 * header and margins (5.5rem), so the board fills the stage; else 72% of it.
 */
function boardMaxHeight () {
  return matchMedia('(min-width: 900px)').matches ? window.innerHeight - 5.5 * 16 : window.innerHeight * 0.72
}

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
  const onRoom = () => changeBoard(Number(rowsSelect.value), riskSelect.value)
  rowsSelect.addEventListener('change', onRoom)
  riskSelect.addEventListener('change', onRoom)

  const bet = byId('bet')
  bet.value = localStorage.getItem(BET_KEY) ?? '10'
  for (const button of document.querySelectorAll('[data-bet]')) {
    button.addEventListener('click', () => changeBet(button.dataset.bet))
  }
  byId('drop').addEventListener('click', () => drop())
  byId('board').addEventListener('click', () => drop())
  byId('auto-rule').textContent = STOP_RULE
  byId('auto').addEventListener('click', toggleAuto)
  byId('auto-resume').addEventListener('click', resumeAuto)
  byId('session-reset').addEventListener('click', resetSession)
  const mute = byId('mute')
  const showMute = () => {
    mute.setAttribute('aria-pressed', String(sound.muted))
    mute.setAttribute('aria-label', sound.muted ? 'Unmute sound' : 'Mute sound')
    mute.title = sound.muted ? 'Sound off (M)' : 'Sound on (M)'
  }
  const toggleMute = () => { sound.setMuted(!sound.muted); showMute() }
  mute.addEventListener('click', toggleMute)
  showMute()

  // Keys: Space drops, S halves, D doubles, A starts or stops the auto-bet,
  // M mutes; none while typing text. Space belongs to a focused control
  // (a button presses, a summary opens): it drops only when nothing
  // interactive has focus, or the Drop button has it.
  const keys = {
    Space: () => drop(),
    KeyS: () => changeBet('half'),
    KeyD: () => changeBet('double'),
    KeyA: toggleAuto,
    KeyM: toggleMute
  }
  document.addEventListener('keydown', (event) => {
    const action = keys[event.code]
    if (!action || event.ctrlKey || event.metaKey || event.altKey || isTyping(event.target) || recall.isOpen) return
    if (event.code === 'Space' && !spaceDrops(event.target)) return
    event.preventDefault()
    if (!event.repeat) action()
  })
  // Space on the focused Drop button would click it as well: the keydown above already dropped.
  document.addEventListener('keyup', (event) => {
    if (event.code === 'Space' && event.target === byId('drop') && !recall.isOpen) event.preventDefault()
  })
}

/** Space drops from the Drop button, or when what has focus is nothing a user operates. */
function spaceDrops (target) {
  if (target === byId('drop')) return true
  if (!(target instanceof Element)) return true
  return target.closest('button, a[href], input, select, textarea, summary, [tabindex], [contenteditable=""], [contenteditable="true"], [role="button"]') === null
}

/** Typing text (where Space and letters are the user's): text fields, text areas, selects, editable content. */
function isTyping (target) {
  if (!(target instanceof HTMLElement)) return false
  if (target.isContentEditable || target.tagName === 'TEXTAREA' || target.tagName === 'SELECT') return true
  return target.tagName === 'INPUT' && !['number', 'range', 'checkbox', 'radio', 'button', 'submit'].includes(/** @type {HTMLInputElement} */ (target).type)
}

/** What tests (and curious players) can read. */
window.__plinko = {
  get ready () { return state.joinedRoom !== null },
  /** performance.now() of the first frame with the board drawn (for scripts/page-load.js), or null. */
  get firstBoardFrameAt () { return firstBoardFrameAt },
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
  get revealedSeeds () { return fairness.revealedSeeds },
  get snapshotChecks () { return { ...snapshotChecks } },
  /** 'seeds' or 'snapshots': how the joined room is delivered */
  get delivery () { return state.view instanceof SeededRoom ? 'seeds' : state.view ? 'snapshots' : null },
  get seeds () {
    const view = state.view instanceof SeededRoom ? state.view : null
    return { ...state.seeds, desyncs: state.seeds.desyncs.map((d) => ({ ...d })), room: view ? { ...view.stats, inFlight: view.drops.size } : null, trace: view?.trace ?? null }
  },
  /** Seeds mode: records every drawn ball position (drop id, render tick, x, y). */
  startSeedsTrace: () => { if (state.view instanceof SeededRoom) state.view.trace = [] },
  get timeline () { return state.timeline ? { ...state.timeline.stats, delayMs: state.timeline.delayMs, jitterMs: state.timeline.jitterMs, ticksPerSecond: state.timeline.rate * 1000 } : null },
  get frames () { return renderer.frames },
  get warnings () { return state.warnings.slice() },
  /** balls drawn in the last frame, and how many of them no announcement explains */
  get lastFrame () { return { ...state.lastFrame } },
  get ownInFlight () { return state.view ? state.view.ownInFlight : 0 },
  get effects () { return { ...renderer.effects, floaterTexts: renderer.floaterTexts.slice(), floating: renderer.floaters.length } },
  get labels () { return renderer.labels.map((l) => ({ ...l })) },
  get sound () { return { muted: sound.muted, unlocked: sound.unlocked, state: sound.context ? sound.context.state : null, ...sound.played } },
  get recent () { return recent.entries.map((e) => ({ ...e })) },
  get feed () { return feed.entries.map((e) => ({ ...e })) },
  get players () { return state.players },
  get session () { return stats.summary },
  /** what the live region said, latest last */
  get announcements () { return announcer.said.slice() },
  get auto () {
    const run = state.autoRun
    return run ? { running: run.running && state.autoTimer !== null, stopReason: run.stopReason, sent: run.sent, settled: run.settled, inFlight: run.inFlight, finished: run.finished, stoppedAt: run.stoppedAt && { ...run.stoppedAt }, remaining: run.remaining, profit: run.profit, bet: run.bet, log: run.log.slice(), dropIds: [...run.dropIds] } : null
  },
  get recall () { return recall.state },
  get firstBoardFrameAt () { return state.firstBoardFrameAt },
  engineVersion: ENGINE_VERSION,
  drop: () => drop(),
  join: (roomId) => join(roomId),
  dropConnection: () => socket.drop(),
  /** Starts recording every rendered frame (render tick, balls, largest distance from the simulated path). */
  startTrace: () => { state.trace = [] },
  get trace () { return state.trace }
}

/** When the first frame with the board was drawn (performance.now()). */
let firstBoardFrameAt = null

function main () {
  setUpControls()
  renderAutoButton()
  updateSummary()
  // The board of the room about to be joined, drawn at once: its space is
  // reserved from the first frame, and nothing moves when the room answers.
  const { rows, risk } = parseRoomId(state.roomId)
  renderer.setBoard(verifier.board(rows, risk))
  requestAnimationFrame((now) => { firstBoardFrameAt = performance.now(); frame(now) })
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
  // One read of the newest drops for both the history and the session's results.
  const firstPage = session.request('GET', `/api/drops?limit=${HISTORY_LIMIT}`).then(({ drops }) => ({ drops, limit: HISTORY_LIMIT }))
  firstPage.catch(() => {})
  await Promise.all([loadHistory(firstPage), fairness.loadSeeds(), restoreSession(state.playerId, firstPage)])
  socket.start()
}

main()
