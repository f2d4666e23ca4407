import { apiRequest } from './api.js'
import { byId } from './dom.js'
import { GameSocket, CLOSE_UNAUTHORIZED } from './game-socket.js'
import { decodeSnapshot, splitRoomFrame } from '/protocol/snapshot-codec.js'
import { parseRoomId, roomIdOf } from '/protocol/room-id.js'
import { socketUrl } from './socket-url.js'
import { SnapshotTimeline } from './snapshot-timeline.js'
import { RoomView } from './room-view.js'
import { SeededRoom } from './seeded-room.js'
import { WorkerSeededRoom } from './worker-seeded-room.js'
import { RoomClock } from './room-clock.js'
import { pageDelivery, applyDropEvents, applyPong, reportDesync, isSeededView, DELIVERY_SNAPSHOTS } from './seeds-delivery.js'

const ROOM_KEY = 'plinko.room'
/** E_WRONG_NODE redirects followed in a row without a join; past this the page stops and says so. */
const MAX_REDIRECTS = 3
/** How often the room's player count is asked for (GET /api/rooms). */
const PLAYERS_EVERY_MS = 4000

/**
 * The page's socket and the room it is in: `welcome` and `join`, the
 * room's view and clock built from `joined` (the page's own simulation in
 * seeds mode, the server's snapshots otherwise: the delivery asked for,
 * snapshots for a server without seeds and for a room that desynced),
 * E_WRONG_NODE redirects to the process that runs the room, the binary
 * frames, and the room's player count. Messages about drops go to
 * DropResults.
 */
export class RoomConnection {
  /** @param {import('./player.js').PlayerPage} page */
  constructor (page) {
    this.page = page
    this.roomId = initialRoom()
    /** @type {string | null} the room the server says we are in */
    this.joinedRoom = null
    /** Where the socket connects: this page's directory, or the process E_WRONG_NODE named. */
    this.socketBase = new URL('.', location.href).href
    this.redirects = 0
    /** @type {RoomView | SeededRoom | WorkerSeededRoom | null} */
    this.view = null
    /**
     * Where a seeds room is simulated: in the board worker beside the drawing, when the board
     * is drawn there (at 100 balls 2.0–2.8 ms of main thread a frame against 3.9–7.9, docs/client.md),
     * or on the main thread with `?simulation=main` (and wherever the board is drawn on it).
     */
    this.simulateInWorker = new URLSearchParams(location.search).get('simulation') !== 'main'
    /** @type {SnapshotTimeline | RoomClock | null} */
    this.timeline = null
    /** The delivery mode asked for in `join` (seeds-delivery.js), and the rooms switched to snapshots after a desync. */
    this.delivery = pageDelivery(location.search)
    this.snapshotRooms = new Set()
    /** Seeds mode: binary frames that were not drop events, and the desyncs seen. */
    this.seeds = { otherFrames: 0, desyncs: [] }
    /** the room whose drops the feed shows */
    this.feedRoom = null
    /** @type {number | null} players in the joined room */
    this.players = null
    this.playersTimer = null
    this.status = 'connecting'
    this.socket = new GameSocket({
      url: () => socketUrl(this.socketBase, page.session.token ?? ''),
      onMessage: (message) => this.handleMessage(message),
      onBinary: (frame, receivedAt) => this.handleFrame(frame, receivedAt),
      onStatus: (status, detail) => this.showStatus(status, detail),
      onClose: (code) => this.onClose(code)
    })
  }

  /** @returns {boolean} whether the socket reconnects by itself */
  onClose (code) {
    const { session, history, results, auto, notices } = this.page
    this.joinedRoom = null
    auto.disconnected()
    if (code !== CLOSE_UNAUTHORIZED) return true
    // The server no longer knows this session (a new database): start a new one.
    session.renew().then(() => {
      history.clear()
      results.loadHistory()
      this.socket.start()
    }, (error) => notices.say(`Could not start a new session: ${error.message}`, 'error'))
    return false
  }

  handleMessage (message) {
    const { results, account } = this.page
    switch (message.type) {
      case 'welcome': return this.onWelcome(message)
      case 'joined': return this.onJoined(message)
      case 'dropped': return results.dropped(message)
      case 'settled': return results.settled(message)
      case 'error': return this.onError(message)
      case 'balance': return account.setBalance(message.balance)
      case 'events': return this.handleRoomEvents(message.events)
      case 'pong': return applyPong(message, performance.now(), { room: this.joinedRoom, clock: this.timeline })
    }
  }

  onWelcome (message) {
    const { account, fairness, checks, results } = this.page
    account.playerId = message.playerId
    account.minBet = message.minBet
    account.maxBet = message.maxBet
    account.setBalance(message.balance)
    fairness.update({ serverSeedHash: message.serverSeedHash, clientSeed: message.clientSeed, nonce: message.nonce })
    byId('bet').min = String(message.minBet)
    byId('bet').max = String(message.maxBet)
    checks.checkEngine(message.engineVersion)
    this.join(this.roomId)
    if (this.socket.connects > 1) results.reconcile()
  }

  onJoined (message) {
    const { verifier, renderer, checks, results, feed, notices, auto } = this.page
    this.redirects = 0
    const parsed = parseRoomId(message.room)
    const board = verifier.board(parsed.rows, parsed.risk, message.engineVersion)
    checks.checkBoard(message.room, board, message.board)
    this.joinedRoom = message.room
    this.openView(message, board, parsed)
    this.timeline.observe(message.tick, performance.now())
    renderer.setBoard(board)
    const inRoom = new Set()
    for (const ball of message.balls) {
      inRoom.add(ball.dropId)
      this.track({ ...ball, room: message.room })
    }
    // Other players' drops that were announced before and are not here any more: their settlements will not reach us.
    verifier.forget((local) => !local.mine && !inRoom.has(local.dropId))
    results.viewChanged(this.view)
    if (this.feedRoom !== message.room) feed.clear()
    this.feedRoom = message.room
    byId('room-name').textContent = message.room
    this.refreshPlayers()
    notices.say(`Joined room ${message.room}.`)
    auto.rejoined()
  }

  /** The joined room's view and clock, for the delivery the server chose. */
  openView (message, board, parsed) {
    const { verifier, snapshotChecks, renderer } = this.page
    if (this.view instanceof WorkerSeededRoom) this.view.close()
    const worker = this.simulateInWorker ? renderer.worker : null
    if (message.delivery === 'seeds' && worker) {
      // The page simulates the room itself, in the board worker beside the drawing (board-worker-room.js).
      this.timeline = new RoomClock({ tickRate: message.tickRate, rttMs: () => this.socket.rttMs })
      this.view = new WorkerSeededRoom({ room: message.room, board, boardOf: parsed, worker, clock: this.timeline })
      // The worker is gone (the board is drawn here now): join again, to simulate the room here.
      renderer.onFallBack = () => { if (this.view instanceof WorkerSeededRoom) this.join(this.roomId) }
    } else if (message.delivery === 'seeds') {
      // The page simulates the room itself (seeded-room.js) at the room's tick.
      this.view = new SeededRoom({ room: message.room, board, boardFor: (engineVersion) => verifier.board(parsed.rows, parsed.risk, engineVersion) })
      this.timeline = new RoomClock({ tickRate: message.tickRate, rttMs: () => this.socket.rttMs })
    } else {
      this.view = new RoomView({ room: message.room, board, snapshotChecks, snapshotEvery: message.snapshotEvery })
      this.timeline = new SnapshotTimeline({ tickRate: message.tickRate, snapshotEvery: message.snapshotEvery })
    }
  }

  onError (message) {
    if (message.code === 'E_WRONG_NODE') return this.followRedirect(message)
    if (message.ref === 'join' && this.delivery !== DELIVERY_SNAPSHOTS && (message.code === 'E_BAD_DELIVERY' || message.code === 'E_BAD_MESSAGE')) {
      // A server without the seeds delivery: snapshots it is.
      this.delivery = DELIVERY_SNAPSHOTS
      return this.join(this.roomId)
    }
    this.page.notices.say(`${message.code}: ${message.message}`, 'error')
    this.page.auto.refused(message)
  }

  /**
   * Clustered, the room runs on another process: reconnect there (the
   * `welcome` handler joins the room again). Bounded, so two processes that
   * disagree cannot bounce the page for ever.
   */
  followRedirect (message) {
    if (message.room !== this.roomId) return
    const { notices } = this.page
    if (this.redirects >= MAX_REDIRECTS || socketUrl(message.owner, '') === null) {
      notices.say(`Room ${message.room} runs on ${message.owner}, which this page could not join: reload to try again.`, 'error')
      return
    }
    this.redirects++
    this.socketBase = message.owner
    this.joinedRoom = null
    notices.say(`Room ${message.room} runs on another server; moving there…`)
    this.socket.reconnectNow()
  }

  join (roomId) {
    this.roomId = roomId
    localStorage.setItem(ROOM_KEY, roomId)
    const delivery = this.snapshotRooms.has(roomId) ? DELIVERY_SNAPSHOTS : this.delivery
    this.socket.send({ type: 'join', room: roomId, delivery, ref: 'join' })
  }

  /** A binary frame: drop events in seeds mode, else a room frame (events and a snapshot). */
  handleFrame (frame, receivedAt) {
    if (isSeededView(this.view)) return this.onDropEvents(frame, receivedAt)
    const split = splitRoomFrame(frame)
    if (!split) return
    this.handleRoomEvents(split.events)
    const snapshot = decodeSnapshot(split.snapshot)
    if (!snapshot || !this.view || !this.timeline) return
    this.view.check(snapshot)
    this.timeline.push(snapshot, receivedAt)
  }

  /** Seeds mode: other players' drops go on the board, and the page's simulation is checked against the server's hash. */
  onDropEvents (frame, receivedAt) {
    const room = this.joinedRoom
    const view = this.view
    const applied = applyDropEvents(frame, receivedAt, { view, clock: this.timeline, add: (event) => this.track({ ...event, room }) })
    if (applied === null) { this.seeds.otherFrames++; return }
    // Our own `settled` rides in the room's frame (the owner's section), after its events.
    for (const message of applied.own) this.handleMessage(message)
    if (applied.check instanceof Promise) applied.check.then((check) => this.onCheck(check, view, room))
    else this.onCheck(applied.check, view, room)
  }

  /** The desync check of a drop-events frame: a room whose simulation disagrees with the server's is shown from snapshots. */
  onCheck (check, view, room) {
    if (check === null || check.ok || view !== this.view) return
    const desync = { room, tick: check.tick, server: check.server, local: check.local, ballsInFlight: check.balls, engineVersion: view.board.engineVersion }
    this.seeds.desyncs.push(desync)
    this.page.notices.say(`This page's simulation of room ${room} disagrees with the server's at tick ${check.tick}: showing the server's positions instead.`, 'error')
    this.snapshotRooms.add(room)
    this.join(room)
    reportDesync(desync, this.page.session.token).then((sent) => { desync.reported = sent })
  }

  /**
   * The other players' `dropped`/`settled` of a snapshot period (in a room
   * frame, or an `events` message), handled as if each had come on its own.
   * Our own are skipped: they come on their own at once, with the balance.
   */
  handleRoomEvents (events) {
    for (const event of events) {
      if (event.player !== this.page.account.playerId && (event.type === 'dropped' || event.type === 'settled')) this.handleMessage(event)
    }
  }

  /** Simulates an announced drop and, if it is in this room, shows its ball. */
  track (announced) {
    const parsed = parseRoomId(announced.room)
    if (!parsed) return
    const { verifier, account } = this.page
    const live = announced.room === this.joinedRoom && isSeededView(this.view)
    // Seeds mode: the ball's own simulation on the board gives the outcome the verifier checks.
    const local = live ? verifier.expect(announced, parsed, account.playerId) : verifier.simulate(announced, parsed, account.playerId)
    if (announced.room === this.joinedRoom && this.view) this.view.add(local)
  }

  /** The room's player count (GET /api/rooms), refreshed while in the room. */
  async refreshPlayers () {
    clearTimeout(this.playersTimer)
    const room = this.joinedRoom
    if (!room) return
    try {
      const { rooms } = await apiRequest('GET', '/api/rooms')
      const here = rooms.find((r) => r.id === room)
      if (room === this.joinedRoom) {
        this.players = here ? here.players : null
        byId('room-players').textContent = this.players === null ? '– players' : `${this.players} player${this.players === 1 ? '' : 's'}`
      }
    } catch {}
    if (room === this.joinedRoom) this.playersTimer = setTimeout(() => this.refreshPlayers(), PLAYERS_EVERY_MS)
  }

  /** The connection pill in the header. */
  showStatus (status, detail) {
    this.status = status
    this.page.auto.connectionChanged(status === 'open')
    const pill = byId('connection')
    pill.dataset.status = status
    pill.title = status
    byId('connection-text').textContent = status === 'open'
      ? 'online'
      : status === 'waiting'
        ? `reconnecting in ${(detail.retryInMs / 1000).toFixed(1)} s`
        : status === 'connecting' ? (detail.attempt > 0 ? 'reconnecting…' : 'connecting…') : 'offline'
  }
}

function initialRoom () {
  const stored = localStorage.getItem(ROOM_KEY)
  return parseRoomId(stored) ? stored : roomIdOf(16, 'medium')
}
