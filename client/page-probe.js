import { ENGINE_VERSION } from '/engine/index.js'
import { isSeededView } from './seeds-delivery.js'

/**
 * What tests (and curious players) can read and do: window.__plinko.
 * @param {import('./player.js').PlayerPage} page
 */
export function installProbe (page) {
  const { connection, account, verifier, history, fairness, renderer, sound, loop } = page
  const seededView = () => isSeededView(connection.view) ? connection.view : null
  window.__plinko = {
    get ready () { return connection.joinedRoom !== null },
    get playerId () { return account.playerId },
    get balance () { return account.balance },
    get room () { return connection.joinedRoom },
    get status () { return connection.status },
    get connects () { return connection.socket.connects },
    /** where the socket connects (changes after an E_WRONG_NODE redirect) */
    get socketBase () { return connection.socketBase },
    get verifications () { return verifier.results.map((v) => ({ ...v })) },
    get pendingVerifications () { return verifier.pending.size },
    get history () { return history.entries },
    get fairnessChecks () { return fairness.checks.map((c) => ({ ...c })) },
    get lastReveal () { return fairness.lastReveal },
    get revealedSeeds () { return fairness.revealedSeeds },
    get snapshotChecks () { return { ...page.snapshotChecks } },
    /** 'seeds' or 'snapshots': how the joined room is delivered */
    get delivery () { return seededView() ? 'seeds' : connection.view ? 'snapshots' : null },
    get seeds () {
      const view = seededView()
      return { ...connection.seeds, desyncs: connection.seeds.desyncs.map((d) => ({ ...d })), room: view ? { ...view.stats, inFlight: view.drops.size } : null, trace: view?.trace ?? null }
    },
    /** Seeds mode: where the joined room is simulated ('worker': beside the board's drawing; 'main'), or null. */
    get simulatedIn () { const view = seededView(); return view ? (view.drawsInWorker ? 'worker' : 'main') : null },
    /** Seeds mode: records every drawn ball position (drop id, render tick, x, y). */
    startSeedsTrace: () => { const view = seededView(); if (view) view.trace = [] },
    get timeline () {
      const t = connection.timeline
      return t ? { ...t.stats, delayMs: t.delayMs, jitterMs: t.jitterMs, ticksPerSecond: t.rate * 1000 } : null
    },
    get frames () { return renderer.frames },
    /** 'worker' (OffscreenCanvas) or 'main': where the board is drawn */
    get boardDrawnIn () { return renderer.drawnIn },
    /** The board's pixels as drawn: { width, height, data } (device px, RGBA), read where it is drawn. */
    boardPixels: () => renderer.pixels(),
    get warnings () { return page.notices.warnings.slice() },
    /** balls drawn in the last frame, and how many of them no announcement explains */
    get lastFrame () { return { ...loop.lastFrame } },
    get ownInFlight () { return connection.view ? connection.view.ownInFlight : 0 },
    get effects () { return { ...renderer.effects, floaterTexts: renderer.floaterTexts.slice(), floating: renderer.floating } },
    get labels () { return renderer.labels.map((l) => ({ ...l })) },
    get sound () { return { muted: sound.muted, unlocked: sound.unlocked, state: sound.context ? sound.context.state : null, ...sound.played } },
    get recent () { return page.recent.entries.map((e) => ({ ...e })) },
    get feed () { return page.feed.entries.map((e) => ({ ...e })) },
    get players () { return connection.players },
    get session () { return page.stats.summary },
    /** what the live region said, latest last */
    get announcements () { return page.announcer.said.slice() },
    get auto () { return page.auto.probe },
    get recall () { return page.recall.state },
    /** performance.now() of the first frame with the board drawn (for scripts/page-load.js), or null. */
    get firstBoardFrameAt () { return loop.firstBoardFrameAt },
    engineVersion: ENGINE_VERSION,
    drop: () => page.bets.drop(),
    join: (roomId) => connection.join(roomId),
    dropConnection: () => connection.socket.drop(),
    /** Starts recording every rendered frame (render tick, balls, largest distance from the simulated path). */
    startTrace: () => { loop.trace = [] },
    get trace () { return loop.trace }
  }
}
