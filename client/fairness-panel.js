import { sha256Hex, MIN_ROWS, MAX_ROWS, ENGINE_VERSIONS, ENGINE_VERSION } from '/engine/index.js'
import { byId, el, fill, shortHex } from './dom.js'
import { CLIENT_SEED_PATTERN } from '/protocol/client-messages.js'
import { checkFairness } from './fair-check.js'

/** Client seeds the server accepts (the protocol's rule): 1 to 64 printable ASCII characters. */
const CLIENT_SEED = new RegExp(CLIENT_SEED_PATTERN)

/**
 * The fairness panel: the committed server seed hash, the client seed
 * (settable), the next nonce, rotation (which reveals the previous seed
 * and checks it against its commitment), and verification of any past
 * drop — or any seeds — in the browser.
 */
export class FairnessPanel {
  /**
   * @param {object} options
   * @param {import('./session.js').Session} options.session
   * @param {() => void} options.onRotated the revealed seed changes the history's drops
   * @param {(text: string, kind?: string) => void} options.say status line
   */
  constructor ({ session, onRotated, say }) {
    this.session = session
    this.onRotated = onRotated
    this.say = say
    this.state = { serverSeedHash: null, clientSeed: null, nonce: null }
    /** @type {import('./fair-check.js').FairCheck[]} every check run on this page, for tests */
    this.checks = []
    /** @type {{ previousServerSeed: string, previousServerSeedHash: string, matchesCommitment: boolean } | null} */
    this.lastReveal = null

    this.hashView = byId('seed-hash')
    this.nonceView = byId('seed-nonce')
    this.clientSeedInput = byId('client-seed')
    this.revealed = byId('revealed')
    this.result = byId('verify-result')
    byId('client-seed-form').addEventListener('submit', (event) => { event.preventDefault(); this.setClientSeed() })
    byId('rotate').addEventListener('click', () => this.rotate())
    byId('verify-form').addEventListener('submit', (event) => {
      event.preventDefault()
      this.verifyDrop(Number(byId('verify-id').value))
    })
    byId('seeds-form').addEventListener('submit', (event) => { event.preventDefault(); this.verifySeeds() })
    const rows = byId('seeds-rows')
    for (let r = MIN_ROWS; r <= MAX_ROWS; r++) rows.append(el('option', { value: String(r), text: String(r), selected: r === 16 }))
    // Every shipped engine version: a drop verifies under the version it was decided under (shown in its record).
    const engines = byId('seeds-engine')
    for (const version of ENGINE_VERSIONS) engines.append(el('option', { value: version, text: version, selected: version === ENGINE_VERSION }))
  }

  /** @param {{ serverSeedHash?: string, clientSeed?: string, nonce?: number }} changes */
  update (changes) {
    Object.assign(this.state, changes)
    this.hashView.textContent = this.state.serverSeedHash ?? '–'
    this.hashView.title = this.state.serverSeedHash ?? ''
    this.nonceView.textContent = this.state.nonce ?? '–'
    if (document.activeElement !== this.clientSeedInput && this.state.clientSeed !== null) this.clientSeedInput.value = this.state.clientSeed
  }

  async setClientSeed () {
    const clientSeed = this.clientSeedInput.value
    if (!CLIENT_SEED.test(clientSeed)) {
      this.say('A client seed is 1 to 64 printable ASCII characters.', 'error')
      return
    }
    try {
      const reply = await this.session.request('PUT', '/api/seeds/client', { clientSeed })
      this.update(reply)
      this.say(`Client seed set; your next drops use “${reply.clientSeed}”.`)
    } catch (error) {
      this.say(`Could not set the client seed: ${error.message}`, 'error')
    }
  }

  async rotate () {
    const committed = this.state.serverSeedHash
    try {
      const reply = await this.session.request('POST', '/api/seeds/rotate')
      const recomputed = await sha256Hex(reply.previousServerSeed)
      const matchesCommitment = recomputed === reply.previousServerSeedHash && (committed === null || committed === reply.previousServerSeedHash)
      this.lastReveal = { previousServerSeed: reply.previousServerSeed, previousServerSeedHash: reply.previousServerSeedHash, matchesCommitment }
      this.update({ serverSeedHash: reply.serverSeedHash, clientSeed: reply.clientSeed, nonce: reply.nonce })
      this.revealed.replaceChildren(
        el('p', {}, 'Revealed server seed (used for ', el('strong', { text: String(reply.previousNonce) }), ' drops):'),
        el('code', { class: 'seed', id: 'revealed-seed', text: reply.previousServerSeed }),
        el('p', { class: matchesCommitment ? 'ok' : 'bad', id: 'revealed-check' },
          matchesCommitment
            ? `✓ sha256 of it is ${shortHex(recomputed)}, the hash that was committed.`
            : `⚠ sha256 of it is ${shortHex(recomputed)}, NOT the committed ${shortHex(committed ?? reply.previousServerSeedHash)}!`)
      )
      this.onRotated()
    } catch (error) {
      this.say(`Could not rotate the server seed: ${error.message}`, 'error')
    }
  }

  /** Verifies one of the player's drops from its revealed seed. @param {number} dropId */
  async verifyDrop (dropId) {
    byId('verify-id').value = String(dropId)
    if (!Number.isSafeInteger(dropId) || dropId < 1) {
      this.show(null, 'Enter the number of one of your drops.')
      return null
    }
    let record
    try {
      record = await this.session.request('GET', `/api/drops/${dropId}`)
    } catch (error) {
      this.show(null, `Drop #${dropId}: ${error.message}`)
      return null
    }
    if (!record.serverSeed) {
      this.show(null, `Drop #${dropId} was made with the active server seed, which is still secret. Rotate the server seed to reveal it, then verify.`)
      return null
    }
    const check = await checkFairness(record, record)
    this.checks.push(check)
    this.show(check, `Drop #${dropId}`)
    return check
  }

  /** Verifies any seeds typed in (no record to compare: shows the outcome). */
  async verifySeeds () {
    const serverSeed = byId('seeds-server').value
    const clientSeed = byId('seeds-client').value
    const nonce = Number(byId('seeds-nonce').value)
    if (serverSeed === '' || !CLIENT_SEED.test(clientSeed) || !Number.isSafeInteger(nonce) || nonce < 0) {
      this.show(null, 'Enter a server seed, a client seed and a nonce (0 or more).')
      return null
    }
    const check = await checkFairness({ serverSeed, clientSeed, nonce, rows: Number(byId('seeds-rows').value), risk: byId('seeds-risk').value, engineVersion: byId('seeds-engine').value })
    this.checks.push(check)
    this.show(check, `Seeds ${shortHex(serverSeed, 6)} / ${clientSeed} / ${nonce}`)
    return check
  }

  /** @param {import('./fair-check.js').FairCheck | null} check @param {string} title */
  show (check, title) {
    if (!check) {
      this.result.replaceChildren(el('p', { class: 'note', text: title }))
      return
    }
    const names = { commitment: 'sha256(server seed) = committed hash', dropSeed: 'HMAC(server seed, client seed:nonce) = drop seed', bucket: 'bucket', ticks: 'ticks to land', stateHash: 'final state hash' }
    const items = Object.entries(check.checks)
      .filter(([, ok]) => ok !== null)
      .map(([name, ok]) => el('li', { class: ok ? 'ok' : 'bad', text: `${ok ? '✓' : '✗'} ${names[name]}` }))
    fill(this.result,
      el('p', { class: check.ok ? 'verdict ok' : 'verdict bad', id: 'verify-verdict', text: `${title}: ${check.ok ? (items.length ? 'verified in your browser' : 'computed') : 'DOES NOT MATCH'}` }),
      items.length ? el('ul', { class: 'checks' }, ...items) : null,
      el('p', { class: 'note', text: `engine ${check.engineVersion}: bucket ${check.bucket} (${check.multiplier}×) after ${check.ticks} ticks, state ${check.stateHash}; drop seed ${shortHex(check.dropSeed)}` })
    )
  }
}
