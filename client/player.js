import { byId } from './dom.js'
import { Session } from './session.js'
import { parseRoomId } from '/protocol/room-id.js'
import { DropVerifier } from './drop-verifier.js'
import { BoardRenderer } from './board-renderer.js'
import { HistoryView } from './history-view.js'
import { FairnessPanel } from './fairness-panel.js'
import { Sound } from './sound.js'
import { SessionStats } from './session-stats.js'
import { LiveFeed } from './live-feed.js'
import { ResultsStrip } from './results-strip.js'
import { RecallView } from './recall-view.js'
import { SessionHistory } from './session-history.js'
import { Announcer } from './announcer.js'
import { PageNotices } from './page-notices.js'
import { PlayerAccount } from './player-account.js'
import { VerificationView } from './verification-view.js'
import { RoomConnection } from './room-connection.js'
import { DropResults, HISTORY_LIMIT } from './drop-results.js'
import { BetControls } from './bet-controls.js'
import { AutoBetControls } from './auto-bet-controls.js'
import { RenderLoop } from './render-loop.js'
import { installProbe } from './page-probe.js'

/**
 * The player's page: connects with the guest session, joins the chosen
 * room, renders every ball in it from the snapshots, and verifies every
 * drop against its own simulation. Everything the board shows happening —
 * peg glows and ticks, bucket bounces, payouts, big-win bursts — comes
 * from that simulation, at the moment the render clock reaches it; a
 * drop's result (the strip, the feed, the session stats, the floating
 * payout) is revealed once its ball has landed on screen and the server
 * has settled it. State for tests is on window.__plinko (page-probe.js).
 *
 * This file builds the page's parts and starts it; each part owns its
 * state and reaches the others through `page`:
 * - `connection` (room-connection.js): the socket, the room and its view and clock, redirects, the delivery;
 * - `results` (drop-results.js): `dropped`/`settled`, results revealed on landing, the history;
 * - `bets` (bet-controls.js): the controls and keys, Drop;
 * - `auto` (auto-bet-controls.js): the auto-bet's run, form and status;
 * - `checks` (verification-view.js): the verification summary and warnings;
 * - `loop` (render-loop.js): the frames and the footer;
 * - `account` (player-account.js), `notices` (page-notices.js).
 */

/**
 * @typedef {object} PlayerPage
 * @property {Session} session
 * @property {DropVerifier} verifier
 * @property {BoardRenderer} renderer
 * @property {PageNotices} notices
 * @property {PlayerAccount} account
 * @property {{ positions: number, mismatches: number, unknown: number }} snapshotChecks
 * @property {Sound} sound
 * @property {SessionStats} stats
 * @property {LiveFeed} feed
 * @property {ResultsStrip} recent
 * @property {SessionHistory} sessionHistory
 * @property {Announcer} announcer
 * @property {HistoryView} history
 * @property {FairnessPanel} fairness
 * @property {RecallView} recall
 * @property {VerificationView} checks
 * @property {DropResults} results
 * @property {AutoBetControls} auto
 * @property {BetControls} bets
 * @property {RoomConnection} connection
 * @property {RenderLoop} loop
 */

function buildPage () {
  const session = new Session()
  const verifier = new DropVerifier()
  const notices = new PageNotices()
  const page = /** @type {PlayerPage} */ ({
    session,
    verifier,
    renderer: new BoardRenderer(byId('board'), { maxHeight: boardMaxHeight, worker: boardWorkerUrl() }),
    notices,
    account: new PlayerAccount(),
    snapshotChecks: { positions: 0, mismatches: 0, unknown: 0 },
    sound: new Sound(),
    stats: new SessionStats({ wagered: byId('stat-wagered'), profit: byId('stat-profit'), drops: byId('stat-drops'), best: byId('stat-best'), chart: byId('profit-chart') }),
    feed: new LiveFeed(byId('feed')),
    recent: new ResultsStrip(byId('recent')),
    sessionHistory: new SessionHistory(session),
    announcer: new Announcer(byId('announcer'))
  })
  page.history = new HistoryView(byId('history'),
    (dropId) => page.fairness.verifyDrop(dropId).then(() => byId('fairness').scrollIntoView({ behavior: page.renderer.reducedMotion ? 'auto' : 'smooth' })),
    (dropId) => page.recall.open(dropId))
  page.fairness = new FairnessPanel({ session, onRotated: () => page.results.loadHistory(), say: (text, kind) => notices.say(text, kind) })
  page.recall = new RecallView({ session, verifier })
  page.checks = new VerificationView(page)
  page.results = new DropResults(page)
  page.auto = new AutoBetControls(page)
  page.bets = new BetControls(page)
  page.connection = new RoomConnection(page)
  page.loop = new RenderLoop(page)
  return page
}

/**
 * The tallest the board may be (CSS px), as the stylesheet's
 * --board-max-height: on a wide screen the window's height less the
 * header and margins (5.5rem), so the board fills the stage; else 72% of it.
 */
function boardMaxHeight () {
  return matchMedia('(min-width: 900px)').matches ? window.innerHeight - 5.5 * 16 : window.innerHeight * 0.72
}

/**
 * Where the board is drawn: board-worker.js, as the page's <meta
 * name="board-worker"> names it (the server's bundle, with its version),
 * so the drawing's rasterising leaves the main thread; `?board=main`
 * draws on the main thread instead (as browsers without OffscreenCanvas do).
 */
function boardWorkerUrl () {
  if (new URLSearchParams(location.search).get('board') === 'main') return null
  return document.querySelector('meta[name="board-worker"]')?.content ?? new URL('./board-worker.js', import.meta.url)
}

/** @param {PlayerPage} page */
function main (page) {
  page.bets.setUp()
  page.auto.renderButton()
  page.checks.updateSummary()
  // The board of the room about to be joined, drawn at once: its space is
  // reserved from the first frame, and nothing moves when the room answers.
  const { rows, risk } = parseRoomId(page.connection.roomId)
  page.renderer.setBoard(page.verifier.board(rows, risk))
  page.loop.start()
  connect(page)
}

/** Opens the session (retrying while the server is unreachable), then the socket. @param {PlayerPage} page */
async function connect (page) {
  const { session, account, fairness, results } = page
  try {
    const me = await session.open()
    account.playerId = me.playerId
    account.setBalance(me.balance)
    fairness.update(me)
  } catch (error) {
    page.notices.say(`Cannot reach the server (${error.message}); retrying…`, 'error')
    setTimeout(() => connect(page), 3000)
    return
  }
  // One read of the newest drops for both the history and the session's results.
  const firstPage = session.request('GET', `/api/drops?limit=${HISTORY_LIMIT}`).then(({ drops }) => ({ drops, limit: HISTORY_LIMIT }))
  firstPage.catch(() => {})
  await Promise.all([results.loadHistory(firstPage), fairness.loadSeeds(), results.restoreSession(account.playerId, firstPage)])
  page.connection.socket.start()
}

const page = buildPage()
installProbe(page)
main(page)
