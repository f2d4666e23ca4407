import { createBoard, simulateDrop, isEngineVersion, ENGINE_VERSIONS } from '/engine/index.js'
import { apiRequest } from './api.js'
import { byId, el, fill, exactAmount, exactMultiplier, formatAmount, formatMultiplier, formatLocalTime } from './dom.js'
import { BoardRenderer } from './board-renderer.js'
import { ReplayPlayer } from './replay-player.js'
import { checkFairness } from './fair-check.js'
import { shareLinkPath, sharedDropPath, shareToken } from './share-link.js'

/**
 * A shared drop (/share/:id/:token), for anyone with the link: fetched
 * from GET /api/share/:id/:token, replayed from its drop seed and, once
 * its server seed is revealed, verified here in the viewer's browser
 * (sha256 of the server seed is the commitment, the drop seed is its HMAC
 * of client seed and nonce, the simulation gives the recorded outcome).
 * Before that the page says when it becomes verifiable. State for tests is
 * on window.__share.
 */

const state = { status: 'loading', verified: null, verifiable: null, record: null, error: null }
window.__share = state

const renderer = new BoardRenderer(byId('share-board'), {
  maxHeight: () => Math.min(620, window.innerHeight * 0.6),
  onResize: () => player.trajectory && player.render()
})
const player = new ReplayPlayer(renderer, () => {})
byId('share-play').addEventListener('click', () => { player.seek(0); player.play() })

async function main () {
  const match = /^\/share\/(\d+)\/([0-9a-f]+)$/.exec(location.pathname)
  if (!match) return fail('This is not a share link.')
  let record
  try {
    record = await apiRequest('GET', sharedDropPath(match[1], match[2]))
  } catch (error) {
    return fail(error.status === 404 ? 'No drop is shared with this link.' : `Could not load the drop: ${error.message}`)
  }
  state.record = record
  byId('share-title').textContent = `Drop #${record.id} · ${record.multiplier === null ? 'in flight' : formatMultiplier(record.multiplier)}`
  byId('share-summary').textContent = record.status === 'settled'
    ? `Player ${record.player} bet ${formatAmount(record.bet)} on ${record.rows} rows, ${record.risk} risk, and won ${formatAmount(record.payout)} (${formatMultiplier(record.multiplier)}).`
    : `Player ${record.player} bet ${formatAmount(record.bet)} on ${record.rows} rows, ${record.risk} risk; the ball is still falling.`
  if (!isEngineVersion(record.engineVersion)) {
    return fail(`This drop was decided under engine ${record.engineVersion}; this page has ${ENGINE_VERSIONS.join(', ')}: reload the page.`)
  }
  const board = createBoard({ rows: record.rows, risk: record.risk, engineVersion: record.engineVersion })
  const outcome = simulateDrop(board, record.dropSeed, { trajectory: true })
  const replayed = record.status === 'settled' && outcome.bucket === record.bucket && outcome.ticks === record.ticks && outcome.stateHash === record.stateHash
  // The link itself is the drop seed's: a page that computes another token was handed another drop.
  const linkOk = shareLinkPath(record.id, await shareToken(record.dropSeed)) === location.pathname
  const chain = record.serverSeed ? await checkFairness(record, record) : null
  state.verifiable = Boolean(record.serverSeed)
  state.verified = chain ? chain.ok && replayed && linkOk : null
  state.status = 'shown'
  const verdict = byId('share-verdict')
  if (!replayed || !linkOk || (chain && !chain.ok)) {
    verdict.className = 'verdict bad'
    verdict.textContent = record.status !== 'settled'
      ? 'This drop has not landed yet: its outcome is not recorded.'
      : '⚠ This browser\'s check does NOT match the recorded drop.'
    state.verified = record.status === 'settled' ? false : null
  } else if (chain) {
    verdict.className = 'verdict ok'
    verdict.textContent = '✓ Verified in this browser: sha256(server seed) is the hash committed before the drop, the drop seed is HMAC(server seed, client seed:nonce), and replaying it gives the recorded bucket, ticks and final state.'
  } else {
    verdict.className = 'verdict'
    verdict.textContent = 'Replayed from its drop seed: same bucket, ticks and final state as recorded. Not verifiable yet: the server seed behind it stays secret until the player rotates it; then this link shows it and checks the whole chain here.'
  }
  const row = (name, value, id) => [el('dt', { text: name }), el('dd', { id, class: typeof value === 'string' && value.length > 24 ? 'seed' : '', text: String(value) })]
  fill(byId('share-data'),
    ...row('Player', record.player),
    ...row('Room', `${record.room} (engine ${record.engineVersion})`),
    ...row('Bet → payout', `${exactAmount(record.bet)} → ${exactAmount(record.payout)} (${record.multiplier === null ? '–' : exactMultiplier(record.multiplier)})`),
    ...row('Bucket, ticks', `${record.bucket ?? '–'} after ${record.ticks ?? '–'} ticks`),
    ...row('Server seed hash (committed)', record.serverSeedHash),
    ...row('Server seed', record.serverSeed ?? 'secret until the player rotates their server seed', 'share-server-seed'),
    ...row('Client seed · nonce', `${record.clientSeed} · ${record.nonce}`),
    ...row('Drop seed', record.dropSeed),
    ...row('Played', formatLocalTime(record.createdAt)),
    ...row('Played (UTC, as recorded)', record.createdAt))
  player.load(board, outcome.trajectory, outcome.bucket)
  player.play()
}

function fail (text) {
  state.status = 'error'
  state.error = text
  const verdict = byId('share-verdict')
  verdict.className = 'verdict bad'
  verdict.textContent = text
}

main()
