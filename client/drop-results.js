import { formatAmount } from './dom.js'
import { parseRoomId } from '/protocol/room-id.js'
import { bucketColors, bucketTextColors } from './board-renderer.js'
import { BIG_WIN } from './live-feed.js'

/** A floating "+payout" for own wins of this multiple or more (BIG_WIN and up: the big celebration). */
const FLOAT_WIN = 2
/** A result that comes this soon after its ball landed on screen still gets its effects (seeds mode draws close to the room's tick). */
const LATE_RESULT_MS = 1000
/** Drops in the history table (GET /api/drops?limit=). */
export const HISTORY_LIMIT = 50

/**
 * The drops' results, each revealed once its ball has landed on screen and
 * the server has settled it: the player's own in the strip above the
 * board, the session stats, the history table and the floating payout;
 * everyone's in the room's feed. After a reload or a reconnect, from the
 * server's history.
 */
export class DropResults {
  /** @param {import('./player.js').PlayerPage} page */
  constructor (page) {
    this.page = page
    /** @type {Map<number, any>} own `settled` messages whose ball has not landed on screen yet */
    this.settledUnseen = new Map()
    /** @type {Set<number>} own drops announced to this page (results revealed once each) */
    this.ownDrops = new Set()
    /** @type {Set<number>} own drops whose result is shown */
    this.revealed = new Set()
  }

  /** `dropped`: a ball for the board; the player's own also into the history. */
  dropped (message) {
    const { account, connection, auto, checks, history } = this.page
    const mine = message.player === account.playerId
    if (message.room === connection.joinedRoom || mine) connection.track(message)
    if (!mine) return
    account.setBalance(message.balance)
    this.ownDrops.add(message.dropId)
    auto.dropped(message)
    checks.checkOwnDrop(message)
    history.upsert(message.dropId, { room: message.room, bet: message.bet })
  }

  /** `settled`: verified, then shown in the feed and (own) revealed once its ball has landed on screen. */
  settled (message) {
    const { account, connection, verifier, checks, auto, history } = this.page
    const here = message.room === connection.joinedRoom
    // Seeds mode: the ball's simulation may not have reached its landing yet.
    if (here) connection.view?.complete?.(message.dropId)
    const verification = verifier.settle(message)
    checks.report(verification)
    const local = here ? connection.view?.drops.get(message.dropId) : undefined
    if (here) {
      // Shown in the feed when its ball lands on screen (or now, if it is not on this board).
      if (local && !local.landingShown) local.settled = message
      else this.addToFeed(message, local)
    }
    if (message.player !== account.playerId) return
    account.setBalance(message.balance)
    auto.result(message)
    if (local && !local.landingShown) this.settledUnseen.set(message.dropId, message)
    else this.reveal(message, local?.landedOnScreenAt !== undefined && performance.now() - local.landedOnScreenAt < LATE_RESULT_MS)
    history.upsert(message.dropId, {
      room: message.room,
      bet: message.bet,
      multiplier: message.multiplier,
      payout: message.payout,
      verified: verification ? verification.verified : null
    })
    checks.updateSummary()
  }

  /** A ball reached its bucket on screen: its feed line, and the player's own result if it has settled. */
  landed (landing) {
    const drop = landing.drop
    if (drop.settled) this.addToFeed(drop.settled, drop)
    else if (drop.result) this.addToFeed(drop.result, drop) // seeds mode: another player's, as simulated here
    const settled = this.settledUnseen.get(landing.dropId)
    if (settled) this.reveal(settled, !landing.stale)
  }

  /** A new room's view: own results waiting for a landing it will not show are revealed now. */
  viewChanged (view) {
    for (const [dropId, settled] of this.settledUnseen) if (!view.drops.has(dropId)) this.reveal(settled, false)
  }

  /**
   * One of the player's results, shown everywhere at once: the strip above
   * the board, the session stats and (for a win of FLOAT_WIN× or more) the
   * floating payout; BIG_WIN× and more get the celebration.
   * @param {any} settled @param {boolean} live the ball just landed on screen (else: effects skipped)
   */
  reveal (settled, live) {
    if (this.revealed.has(settled.dropId) || !this.ownDrops.has(settled.dropId)) return
    const { connection, announcer, renderer } = this.page
    this.settledUnseen.delete(settled.dropId)
    this.showResult(settled, connection.view?.drops.get(settled.dropId)?.engineVersion, true)
    this.rememberShown()
    announcer.result(settled)
    if (!live || settled.room !== connection.joinedRoom) return
    const now = performance.now()
    if (settled.multiplier >= FLOAT_WIN) renderer.floatText(settled.bucket, `+${formatAmount(settled.payout)}`, now, { big: settled.multiplier >= BIG_WIN })
    if (settled.multiplier >= BIG_WIN) renderer.celebrate(settled.bucket, now)
  }

  /**
   * A result into the strip and (`counted`) the session stats, once.
   * @param {{ dropId: number, room: string, bet: number, payout: number, multiplier: number, bucket: number }} settled
   * @param {string} [engineVersion] @param {boolean} counted
   */
  showResult (settled, engineVersion, counted) {
    this.revealed.add(settled.dropId)
    const parsed = parseRoomId(settled.room)
    const board = parsed ? this.page.verifier.board(parsed.rows, parsed.risk, engineVersion) : null
    const colors = board ? bucketColors(board.multipliers) : []
    const textColors = board ? bucketTextColors(board.multipliers) : []
    this.page.recent.add({ dropId: settled.dropId, multiplier: settled.multiplier, bucket: settled.bucket, color: colors[settled.bucket] ?? '#98a3cf', textColor: textColors[settled.bucket] })
    if (counted) this.page.stats.add({ bet: settled.bet, payout: settled.payout, multiplier: settled.multiplier })
  }

  /**
   * A feed line; with the drop as this page knows it, its announced seed
   * too (another player's line is then checkable through its share link).
   * @param {{ dropId: number, player: string, bet: number, multiplier: number, payout: number }} settled
   * @param {{ dropSeed: string }} [drop]
   */
  addToFeed (settled, drop) {
    this.page.feed.add({ dropId: settled.dropId, player: settled.player, mine: settled.player === this.page.account.playerId, bet: settled.bet, multiplier: settled.multiplier, payout: settled.payout, dropSeed: drop?.dropSeed ?? null })
  }

  /**
   * After a reload: this tab session's results back into the strip and the
   * session stats, from the server's history; its drops still falling are
   * the page's own again, so their results show when they settle.
   */
  async restoreSession (playerId, firstPage) {
    try {
      const { drops, statsAfter } = await this.page.sessionHistory.load(playerId, await firstPage)
      for (const record of drops) {
        if (this.revealed.has(record.id)) continue
        if (record.status !== 'settled') { this.ownDrops.add(record.id); continue }
        this.showResult({ dropId: record.id, room: record.room, bet: record.bet, payout: record.payout, multiplier: record.multiplier, bucket: record.bucket }, record.engineVersion, record.id > statsAfter)
      }
      this.rememberShown()
    } catch (error) {
      this.page.notices.say(`Could not load this session's results: ${error.message}`, 'error')
    }
  }

  /** The results column's order, for the next reload (session-history.js). */
  rememberShown () {
    this.page.sessionHistory.rememberShown(this.page.recent.entries.map((entry) => entry.dropId).reverse())
  }

  resetSession () {
    this.page.stats.reset()
    let newest = 0
    for (const id of this.revealed) newest = Math.max(newest, id)
    this.page.sessionHistory.resetStats(newest)
  }

  /** After a reconnect: settle from the ledger what settled while we were away. */
  async reconcile () {
    await this.loadHistory()
    this.page.checks.updateSummary()
  }

  /** @param {Promise<{ drops: any[] }>} [page] the newest drops, if read already */
  async loadHistory (page) {
    const { session, connection, verifier, checks, history, auto } = this.page
    if (!session.token) return
    try {
      const { drops } = await (page ?? session.request('GET', `/api/drops?limit=${HISTORY_LIMIT}`))
      for (const record of drops.slice().reverse()) {
        // Settled while this page was away (a reconnect): its result is final, and shown now.
        if (record.status === 'settled' && this.ownDrops.has(record.id) && !this.revealed.has(record.id) && !connection.view?.drops.has(record.id)) {
          this.reveal({ dropId: record.id, room: record.room, bet: record.bet, multiplier: record.multiplier, payout: record.payout, bucket: record.bucket }, false)
          auto.result({ dropId: record.id, bet: record.bet, payout: record.payout })
        }
        const verification = verifier.settleFromRecord(record)
        checks.report(verification)
        history.upsert(record.id, {
          room: record.room,
          bet: record.bet,
          multiplier: record.multiplier,
          payout: record.payout,
          verified: verification ? verification.verified : null,
          revealed: Boolean(record.serverSeed)
        })
      }
      checks.updateSummary()
    } catch (error) {
      this.page.notices.say(`Could not load your drops: ${error.message}`, 'error')
    }
  }
}
