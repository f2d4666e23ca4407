import { ENGINE_VERSION, isEngineVersion } from '/engine/index.js'
import { byId, shortHex } from './dom.js'

/**
 * What the page says about checking the server: the summary of the drops
 * verified in this browser, a warning for each drop that did not verify,
 * for a board or engine that differs from the page's own, and for a drop
 * made with another server seed than the one committed.
 */
export class VerificationView {
  /** @param {import('./player.js').PlayerPage} page */
  constructor (page) {
    this.page = page
  }

  updateSummary () {
    const total = this.page.verifier.total
    const failed = this.page.verifier.failures
    const summary = byId('verify-summary')
    summary.className = failed > 0 ? 'summary bad' : 'summary ok'
    summary.textContent = total === 0
      ? 'Every drop is simulated in your browser and checked against the server.'
      : failed === 0
        ? `✓ ${total} drop${total === 1 ? '' : 's'} verified in this browser`
        : `⚠ ${failed} of ${total} drops did NOT verify`
  }

  /** A verification the page ran, warned about if it failed. */
  report (verification) {
    if (verification && !verification.verified) this.warnMismatch(verification)
  }

  warnMismatch (v) {
    this.page.notices.warn(`Drop #${v.dropId} did NOT verify: this browser computed bucket ${v.localBucket} after ${v.localTicks} ticks (state ${v.localStateHash}), the server says bucket ${v.serverBucket} after ${v.serverTicks} ticks (state ${v.serverStateHash}).`)
  }

  /** `welcome`: an engine this page does not have cannot verify anything. @param {string} engineVersion */
  checkEngine (engineVersion) {
    if (!isEngineVersion(engineVersion)) {
      this.page.notices.warn(`The server runs engine ${engineVersion}, which this page's engine (up to ${ENGINE_VERSION}) does not have: reload the page. Drops cannot be verified until then.`)
    }
  }

  /** `joined`: the server's board against the one this page's engine builds. */
  checkBoard (room, local, remote) {
    if (!sameBoard(local, remote)) {
      this.page.notices.warn(`The server's board for room ${room} differs from the one this page's engine builds: outcomes shown here may not match.`)
    }
  }

  /** Own `dropped`: the next nonce, and the seed hash it was made with against the committed one. */
  checkOwnDrop (message) {
    const { fairness } = this.page
    fairness.update({ nonce: message.nonce + 1 })
    const committed = fairness.state.serverSeedHash
    if (committed && message.serverSeedHash !== committed) {
      this.page.notices.warn(`Drop #${message.dropId} was made with server seed hash ${shortHex(message.serverSeedHash)}, not the committed ${shortHex(committed)}.`)
    }
  }
}

function sameBoard (local, remote) {
  return remote && local.width === remote.width && local.height === remote.height &&
    JSON.stringify(local.pegs) === JSON.stringify(remote.pegs) &&
    JSON.stringify(local.walls) === JSON.stringify(remote.walls) &&
    JSON.stringify(local.multipliers) === JSON.stringify(remote.multipliers)
}
