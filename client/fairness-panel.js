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
    /** @type {{ serverSeed: string, serverSeedHash: string, nonces: number, revealedAt: string, matches: boolean }[] | null} GET /api/seeds' revealed seeds, checked here; null before it answered */
    this.revealedSeeds = null
    this.revealedList = byId('revealed-seeds')

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
      this.loadSeeds()
    } catch (error) {
      this.say(`Could not rotate the server seed: ${error.message}`, 'error')
    }
  }

  /**
   * Lists the player's revealed server seeds (GET /api/seeds: they survive
   * reloads and new devices), each checked against its commitment here.
   */
  async loadSeeds () {
    let reply
    try {
      reply = await this.session.request('GET', '/api/seeds')
    } catch (error) {
      this.say(`Could not load your revealed server seeds: ${error.message}`, 'error')
      return null
    }
    const seeds = await Promise.all(reply.revealed.map(async (seed) => ({
      serverSeed: seed.serverSeed,
      serverSeedHash: seed.serverSeedHash,
      nonces: seed.nonces,
      revealedAt: seed.revealedAt,
      matches: (await sha256Hex(seed.serverSeed)) === seed.serverSeedHash
    })))
    this.revealedSeeds = seeds
    if (seeds.length === 0) {
      this.revealedList.replaceChildren(el('li', { class: 'note', text: 'None yet: rotating reveals the active seed.' }))
      return seeds
    }
    this.revealedList.replaceChildren(...seeds.map((seed) => el('li', { dataset: { hash: seed.serverSeedHash } },
      el('code', { class: 'seed', text: seed.serverSeed }),
      el('span', { class: seed.matches ? 'ok' : 'bad', text: seed.matches ? ` ✓ sha256 = ${shortHex(seed.serverSeedHash)}` : ` ⚠ sha256 is NOT the committed ${shortHex(seed.serverSeedHash)}` }),
      el('span', { class: 'note', text: ` · ${seed.nonces} drop${seed.nonces === 1 ? '' : 's'} · revealed ${(seed.revealedAt ?? '').replace('T', ' ').slice(0, 19)}` }))))
    return seeds
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

  /**
   * Verifies any seeds typed in. The computed sha256 of the server seed is
   * always shown, and compared with the committed hash of the drop being
   * checked: the one typed in, or else that of the player's own drop with
   * this client seed and nonce (whose outcome is then compared too, when
   * the board and engine chosen are the drop's).
   */
  async verifySeeds () {
    const serverSeed = byId('seeds-server').value.trim()
    const clientSeed = byId('seeds-client').value
    const nonce = Number(byId('seeds-nonce').value)
    const typedCommitment = byId('seeds-commitment').value.trim().toLowerCase()
    if (serverSeed === '' || !CLIENT_SEED.test(clientSeed) || !Number.isSafeInteger(nonce) || nonce < 0) {
      this.show(null, 'Enter a server seed, a client seed and a nonce (0 or more).')
      return null
    }
    if (typedCommitment !== '' && !/^[0-9a-f]{64}$/.test(typedCommitment)) {
      this.show(null, 'A committed hash is 64 hexadecimal digits (or leave it empty to use your drop\'s).')
      return null
    }
    const seeds = { serverSeed, clientSeed, nonce, rows: Number(byId('seeds-rows').value), risk: byId('seeds-risk').value, engineVersion: byId('seeds-engine').value }
    const computedHash = await sha256Hex(serverSeed)
    const drop = await this._dropWith(clientSeed, nonce, computedHash)
    const sameBoard = drop && drop.rows === seeds.rows && drop.risk === seeds.risk && drop.engineVersion === seeds.engineVersion
    /** @type {Record<string, any>} */
    const record = { serverSeedHash: typedCommitment || drop?.serverSeedHash }
    if (drop) {
      record.id = drop.id
      record.dropSeed = drop.dropSeed
      if (sameBoard) Object.assign(record, { bucket: drop.bucket, ticks: drop.ticks, stateHash: drop.stateHash })
    }
    const check = await checkFairness(seeds, record)
    check.committedHash = record.serverSeedHash ?? null
    check.committedFrom = typedCommitment ? 'typed' : drop ? `drop #${drop.id}` : null
    this.checks.push(check)
    this.show(check, drop ? `Seeds of drop #${drop.id}` : `Seeds ${shortHex(serverSeed, 6)} / ${clientSeed} / ${nonce}`)
    return check
  }

  /**
   * The player's drop with this client seed and nonce (nonces restart at 0
   * with each server seed, so several may match: the one this server seed
   * committed to, else the newest), or null.
   */
  async _dropWith (clientSeed, nonce, computedHash) {
    try {
      const { drops } = await this.session.request('GET', '/api/drops?limit=500')
      const matching = drops.filter((d) => d.clientSeed === clientSeed && d.nonce === nonce)
      return matching.find((d) => d.serverSeedHash === computedHash) ?? matching[0] ?? null
    } catch {
      return null
    }
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
    const committed = check.committedHash === undefined ? null : check.committedHash
    fill(this.result,
      el('p', { class: check.ok ? 'verdict ok' : 'verdict bad', id: 'verify-verdict', text: `${title}: ${check.ok ? (items.length ? 'verified in your browser' : 'computed') : 'DOES NOT MATCH'}` }),
      check.committedHash !== undefined
        ? el('div', { class: 'hash-compare', id: 'verify-hashes' },
          el('p', {}, 'sha256 of the server seed entered: ', el('code', { class: 'seed', id: 'verify-computed-hash', text: check.serverSeedHash })),
          committed
            ? el('p', {}, `committed hash (${check.committedFrom}): `, el('code', { class: 'seed', id: 'verify-committed-hash', text: committed }),
              el('strong', { class: committed === check.serverSeedHash ? 'ok' : 'bad', id: 'verify-hash-verdict', text: committed === check.serverSeedHash ? ' ✓ equal' : ' ✗ DIFFERENT: this is not the server seed that was committed' }))
            : el('p', { class: 'note', id: 'verify-hash-verdict', text: 'No committed hash to compare with: none was entered and none of your drops has this client seed and nonce.' }))
        : null,
      items.length ? el('ul', { class: 'checks' }, ...items) : null,
      el('p', { class: 'note', text: `engine ${check.engineVersion}: bucket ${check.bucket} (${check.multiplier}×) after ${check.ticks} ticks, state ${check.stateHash}; drop seed ${shortHex(check.dropSeed)}` })
    )
  }
}
