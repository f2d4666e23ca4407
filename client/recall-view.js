import { simulateDrop, isEngineVersion, ENGINE_VERSIONS } from '/engine/index.js'
import { byId, el, fill, exactAmount, exactMultiplier, formatLocalTime } from './dom.js'
import { BoardRenderer } from './board-renderer.js'
import { ReplayPlayer } from './replay-player.js'
import { checkFairness } from './fair-check.js'
import { shareLink } from './share-link.js'

/**
 * Game recall: any of the player's past drops, fetched from the ledger
 * (GET /api/drops/:id), re-simulated in the browser from its drop seed
 * under its own engine version and replayed on a canvas of its own (play,
 * pause, step, scrub, speed), with its fairness data beside it: the
 * committed hash, the client seed and nonce, the drop seed, and — once
 * the server seed is revealed — the whole chain checked in the browser.
 */
export class RecallView {
  /**
   * @param {object} options
   * @param {import('./session.js').Session} options.session
   * @param {import('./drop-verifier.js').DropVerifier} options.verifier builds (and caches) boards
   */
  constructor ({ session, verifier }) {
    this.session = session
    this.verifier = verifier
    this.dialog = byId('recall')
    this.renderer = new BoardRenderer(byId('recall-board'), {
      maxHeight: () => Math.min(520, window.innerHeight * 0.5),
      onResize: () => this.player.trajectory && this.player.render()
    })
    this.player = new ReplayPlayer(this.renderer, (p) => this._showState(p))
    /** @type {null | { dropId: number, bucket: number, ticks: number, stateHash: string, matches: boolean, chain: boolean | null, record: any }} */
    this.current = null
    byId('recall-close').addEventListener('click', () => this.close())
    byId('recall-play').addEventListener('click', () => this.player.toggle())
    byId('recall-back').addEventListener('click', () => this.player.step(-1))
    byId('recall-forward').addEventListener('click', () => this.player.step(1))
    byId('recall-speed').addEventListener('change', (event) => this.player.setSpeed(Number(event.target.value)))
    byId('recall-scrub').addEventListener('input', (event) => { this.player.pause(); this.player.seek(Number(event.target.value)) })
    this.dialog.addEventListener('close', () => this.player.pause())
    byId('recall-share').addEventListener('click', () => this.share())
  }

  get isOpen () {
    return this.dialog.open
  }

  close () {
    this.player.pause()
    if (this.dialog.open) this.dialog.close()
  }

  /** Opens drop `dropId` and starts its replay. @param {number} dropId */
  async open (dropId) {
    byId('recall-title').textContent = `Game recall · drop #${dropId}`
    fill(byId('recall-data'))
    byId('recall-verdict').textContent = 'Loading…'
    byId('recall-verdict').className = 'verdict'
    byId('recall-share').hidden = true
    byId('recall-share-link').hidden = true
    if (!this.dialog.open) this.dialog.showModal()
    let record
    try {
      record = await this.session.request('GET', `/api/drops/${dropId}`)
    } catch (error) {
      byId('recall-verdict').textContent = `Drop #${dropId}: ${error.message}`
      return null
    }
    if (!isEngineVersion(record.engineVersion)) {
      byId('recall-verdict').textContent = `Drop #${dropId} was decided under engine ${record.engineVersion}; this page has ${ENGINE_VERSIONS.join(', ')}: reload the page.`
      return null
    }
    const board = this.verifier.board(record.rows, record.risk, record.engineVersion)
    const outcome = simulateDrop(board, record.dropSeed, { trajectory: true })
    const settled = record.status === 'settled'
    const matches = settled && outcome.bucket === record.bucket && outcome.ticks === record.ticks && outcome.stateHash === record.stateHash
    const chain = record.serverSeed ? await checkFairness(record, record) : null
    this.current = { dropId, bucket: outcome.bucket, ticks: outcome.ticks, stateHash: outcome.stateHash, matches, chain: chain ? chain.ok : null, record }
    this._showData(record, outcome, matches, chain)
    byId('recall-share').hidden = !settled
    this.player.load(board, outcome.trajectory, outcome.bucket)
    this.player.play()
    return this.current
  }

  _showData (record, outcome, matches, chain) {
    const verdict = byId('recall-verdict')
    const settled = record.status === 'settled'
    verdict.className = `verdict ${!settled ? '' : matches && chain !== false ? 'ok' : 'bad'}`
    verdict.textContent = !settled
      ? 'Still in flight: no outcome recorded yet.'
      : !matches
          ? '⚠ This browser\'s simulation does NOT match the recorded outcome'
          : chain === null
            ? '✓ Replayed from its drop seed: same bucket, ticks and final state as recorded. Rotate your server seed to check the whole chain.'
            : chain
              ? '✓ Replayed and verified: sha256(server seed) is the committed hash, the drop seed is HMAC(server seed, client seed:nonce), and the outcome is the recorded one'
              : '⚠ The revealed server seed does NOT give this drop\'s commitment or drop seed'
    const row = (name, value, id) => [el('dt', { text: name }), el('dd', { id, class: typeof value === 'string' && value.length > 24 ? 'seed' : '', text: String(value) })]
    fill(byId('recall-data'),
      ...row('Room', `${record.room} (engine ${record.engineVersion})`),
      ...row('Bet → payout', `${exactAmount(record.bet)} → ${exactAmount(record.payout)} (${record.multiplier === null ? '–' : exactMultiplier(record.multiplier)})`),
      ...row('Bucket, ticks', `${outcome.bucket} after ${outcome.ticks} ticks (recorded ${record.bucket ?? '–'} after ${record.ticks ?? '–'})`),
      ...row('Final state hash', outcome.stateHash),
      ...row('Server seed hash (committed)', record.serverSeedHash),
      ...row('Server seed', record.serverSeed ?? 'secret until you rotate the server seed', 'recall-server-seed'),
      ...row('Client seed · nonce', `${record.clientSeed} · ${record.nonce}`),
      ...row('Drop seed', record.dropSeed),
      ...row('Played', formatLocalTime(record.createdAt), 'recall-played'),
      ...row('Played (UTC, as recorded)', record.createdAt, 'recall-played-utc'))
  }

  /** A link anyone can open to watch this drop and verify it (/share/:id/:token), shown and copied. */
  async share () {
    const record = this.current?.record
    if (!record) return
    const link = await shareLink(record)
    const field = byId('recall-share-link')
    field.value = link
    field.hidden = false
    field.select()
    try {
      await navigator.clipboard.writeText(link)
      byId('recall-share').textContent = 'Link copied'
    } catch {
      byId('recall-share').textContent = 'Share link'
    }
    this.current.shareLink = link
  }

  _showState (p) {
    byId('recall-play').textContent = p.playing ? '❚❚ Pause' : '▶ Play'
    const scrub = byId('recall-scrub')
    scrub.max = String(p.ticks)
    scrub.value = String(Math.round(p.position))
    byId('recall-tick').textContent = p.trajectory ? `tick ${p.tick} / ${p.ticks}${p.tick >= p.ticks ? ` · bucket ${p.bucket}` : ''}` : ''
  }

  /** For tests. */
  get state () {
    return this.current ? { ...this.current, record: undefined, open: this.isOpen, tick: this.player.tick, playing: this.player.playing, frames: this.renderer.frames } : null
  }
}
