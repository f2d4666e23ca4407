import { createBoard, simulateDrop, rtpStatistics, calibrationOf, isEngineVersion, ENGINE_VERSION, ENGINE_VERSIONS, MIN_ROWS, MAX_ROWS } from '/engine/index.js'
import { apiRequest, query } from './api.js'
import { byId, el, fill, formatAmount, formatMultiplier, exactAmount, exactMultiplier, formatLocalTime, amountTitle, multiplierTitle, shortHex } from './dom.js'
import { BoardRenderer } from './board-renderer.js'
import { ReplayPlayer } from './replay-player.js'
import { checkFairness } from './fair-check.js'
import { payoutMilli, toCredits, toMilli } from '/protocol/payout.js'
import { bucketChart, rtpChart, legend, CHART_COLORS } from './rtp-chart.js'

/**
 * The operator's page (/audit). Every call carries the operator token
 * (kept in sessionStorage: gone when the tab closes). A drop looked up by
 * id or by seeds is shown three ways — the stored record, the server's
 * fresh re-simulation, and this browser's own simulation with the same
 * engine — and replayed on the canvas from its trajectory. State for tests
 * is on window.__audit.
 */

const TOKEN_KEY = 'plinko.operatorToken'
const STATS_REFRESH_MS = 2000
/** The RTP chart starts from the room's recorded history: this many of its latest drops at most (pages of HISTORY_PAGE). */
const HISTORY_DROPS = 5000
const HISTORY_PAGE = 1000
/** Points the history is drawn with. */
const HISTORY_POINTS = 60

const renderer = new BoardRenderer(byId('replay-canvas'), {
  maxHeight: () => Math.min(620, window.innerHeight * 0.7),
  onResize: () => (player?.trajectory ? player.render() : renderer.draw([], performance.now()))
})
const player = new ReplayPlayer(renderer, showReplayState)
const state = {
  token: sessionStorage.getItem(TOKEN_KEY),
  /** the server accepted `token` (set once the check has answered, not while it is asked) */
  signedIn: false,
  /** @type {any[]} */
  lookups: [],
  stats: { room: null, timer: null, samples: [], last: null }
}

/** The server's payout, in credits, under the rule the drop was paid under (protocol/payout.js). */
function payoutFor (bet, multiplier, rule) {
  return toCredits(payoutMilli(bet, multiplier, rule))
}

function operatorGet (path) {
  return apiRequest('GET', path, { token: state.token })
}

// ---- sign-in ----------------------------------------------------------------

/**
 * Signs in through POST /api/audit/token-check, which answers 200 whatever
 * the token: a refused request would be logged by the browser itself in the
 * console, so the audit routes are called only once the token is known
 * good. A wrong token still counts against this address on the server.
 */
async function signIn (token) {
  state.token = token
  state.signedIn = false
  let verdict
  try {
    verdict = await apiRequest('POST', '/api/audit/token-check', { token })
  } catch (error) {
    verdict = { valid: false, message: `Cannot check the token: ${error.message}` }
  }
  if (!verdict.valid) {
    state.token = null
    sessionStorage.removeItem(TOKEN_KEY)
    showAuth(false, refusal(verdict))
    return false
  }
  sessionStorage.setItem(TOKEN_KEY, token)
  state.signedIn = true
  showAuth(true, 'Signed in.')
  showBusiestRoom()
  return true
}

/** What the page says of a refused token. @param {{ code?: string, message?: string, retryAfter?: number }} verdict */
function refusal ({ code, message, retryAfter }) {
  if (code === 'E_RATE_LIMITED') return `Too many wrong tokens from this address: try again in ${retryAfter} s.`
  if (code === 'E_FORBIDDEN' || code === 'E_UNAUTHORIZED') return 'That is not the operator token.'
  return message
}

/** Starts the statistics on the live room with the most balls in flight, if any. */
async function showBusiestRoom () {
  if (state.stats.room) return
  const { rooms } = await apiRequest('GET', '/api/rooms').catch(() => ({ rooms: [] }))
  const busiest = rooms.slice().sort((p, q) => q.ballsInFlight - p.ballsInFlight || q.players - p.players)[0]
  if (!busiest || state.stats.room) return
  byId('stats-rows').value = String(busiest.rows)
  byId('stats-risk').value = busiest.risk
  showStats(busiest.id)
}

function signOut () {
  state.token = null
  state.signedIn = false
  sessionStorage.removeItem(TOKEN_KEY)
  stopStats()
  showAuth(false, 'Signed out.')
}

function showAuth (signedIn, message) {
  const pill = byId('auth-state')
  pill.dataset.status = signedIn ? 'open' : 'stopped'
  pill.textContent = signedIn ? 'operator' : 'signed out'
  byId('login-message').textContent = message
  byId('sign-out').hidden = !signedIn
  byId('token').value = ''
  for (const section of document.querySelectorAll('.lookup, .player-drops, .stats')) section.toggleAttribute('inert', !signedIn)
}

function requireToken () {
  if (state.token) return true
  byId('login-message').textContent = 'Sign in with the operator token first.'
  return false
}

// ---- drop look-up -----------------------------------------------------------

async function lookupById (id) {
  if (!requireToken()) return null
  say(`Looking up drop #${id}…`)
  let audit
  try {
    // Whether it exists first, from the list (a 200 either way): an unknown id is a message here, not a 404 in the console.
    const { drops } = await operatorGet(`/api/audit/drops${query({ before: id + 1, limit: 1 })}`)
    if (drops[0]?.id !== id) {
      say(`Drop #${id}: no drop ${id} is recorded.`, 'error')
      return null
    }
    audit = await operatorGet(`/api/audit/drops/${id}`)
  } catch (error) {
    say(`Drop #${id}: ${error.message}`, 'error')
    return null
  }
  const { drop, replay, checks, matches } = audit
  if (!isEngineVersion(drop.engineVersion)) {
    say(`Drop #${id} was decided under engine ${drop.engineVersion}, which this page's engine (${ENGINE_VERSIONS.join(', ')}) does not have: reload the page.`, 'error')
    return null
  }
  const board = createBoard({ rows: drop.rows, risk: drop.risk, engineVersion: drop.engineVersion })
  const local = simulateDrop(board, drop.dropSeed, { trajectory: true })
  const chain = drop.serverSeed ? await checkFairness(drop, drop) : null
  const browser = {
    engineVersion: board.engineVersion,
    serverSeedHash: chain ? chain.serverSeedHash : null,
    dropSeed: chain ? chain.dropSeed : null,
    bucket: local.bucket,
    multiplier: local.multiplier,
    payout: payoutFor(drop.bet, local.multiplier, drop.payoutRule),
    ticks: local.ticks,
    stateHash: local.stateHash
  }
  const result = record({ dropId: drop.id, drop, replay, browser, serverChecks: checks, serverMatches: matches })
  player.load(board, local.trajectory, local.bucket)
  say(`Drop #${drop.id} by player ${drop.playerId} in room ${drop.room}.`)
  return result
}

async function lookupBySeeds ({ serverSeed, clientSeed, nonce, rows, risk, engineVersion = ENGINE_VERSION }) {
  if (!requireToken()) return null
  say('Verifying seeds…')
  let verified
  try {
    verified = await operatorGet(`/api/audit/verify${query({ serverSeed, clientSeed, nonce, rows, risk, engineVersion })}`)
  } catch (error) {
    say(`Seeds: ${error.message}`, 'error')
    return null
  }
  const chain = await checkFairness({ serverSeed, clientSeed, nonce, rows, risk, engineVersion })
  const stored = verified.recorded.length > 0 ? await operatorGet(`/api/audit/drops/${verified.recorded[0].id}`).catch(() => null) : null
  const board = createBoard({ rows, risk, engineVersion })
  const local = simulateDrop(board, chain.dropSeed, { trajectory: true })
  const bet = stored?.drop.bet ?? null
  const rule = stored?.drop.payoutRule
  const replay = { ...verified, payout: bet === null ? null : payoutFor(bet, verified.multiplier, rule) }
  const browser = {
    engineVersion,
    serverSeedHash: chain.serverSeedHash,
    dropSeed: chain.dropSeed,
    bucket: local.bucket,
    multiplier: local.multiplier,
    payout: bet === null ? null : payoutFor(bet, local.multiplier, rule),
    ticks: local.ticks,
    stateHash: local.stateHash
  }
  const result = record({
    dropId: stored?.drop.id ?? null,
    drop: stored?.drop ?? null,
    replay,
    browser,
    serverChecks: stored?.checks ?? null,
    serverMatches: stored ? stored.matches : null,
    recorded: verified.recorded
  })
  player.load(board, local.trajectory, local.bucket)
  say(stored ? `These seeds are drop #${stored.drop.id}.` : 'No stored drop has these seeds (computed only).')
  return result
}

const FIELDS = ['engineVersion', 'serverSeedHash', 'dropSeed', 'bucket', 'multiplier', 'payout', 'ticks', 'stateHash']

/**
 * Shows stored record / server re-simulation / browser simulation side by
 * side and remembers the outcome for tests.
 */
function record ({ dropId, drop, replay, browser, serverChecks, serverMatches, recorded = null }) {
  const rows = FIELDS.map((field) => {
    const stored = drop ? drop[field] : undefined
    const values = [stored, replay[field], browser[field]]
    const known = values.filter((v) => v !== null && v !== undefined)
    const agree = known.length < 2 ? null : known.every((v) => v === known[0])
    return { field, stored, server: replay[field], browser: browser[field], agree }
  })
  const settled = drop?.status === 'settled'
  const browserMatches = drop
    ? settled && ['bucket', 'ticks', 'stateHash', 'multiplier', 'payout'].every((f) => drop[f] === browser[f]) && drop.dropSeed && (browser.dropSeed === null || browser.dropSeed === drop.dropSeed)
    : ['bucket', 'ticks', 'stateHash', 'dropSeed', 'serverSeedHash'].every((f) => replay[f] === browser[f])
  const matches = Boolean(browserMatches) && serverMatches !== false && rows.every((r) => r.agree !== false)
  const result = { dropId, matches, serverMatches, browserMatches: Boolean(browserMatches), settled, rows, recorded }
  state.lookups.push(result)

  const banner = drop
    ? (matches
        ? 'MATCH — the stored record, the server\'s re-simulation and this browser\'s simulation agree'
        : settled ? 'MISMATCH — see the fields marked ✗' : 'IN FLIGHT — no outcome recorded yet')
    : (matches ? 'Server and browser agree on these seeds (no stored drop uses them)' : 'MISMATCH between server and browser')
  const cell = (value, field) => el('td', { title: value === null || value === undefined ? '' : String(value), text: format(value, field) })
  fill(byId('record'),
    el('div', { class: `banner ${matches ? 'ok' : 'bad'}`, id: 'match-banner', dataset: { matches: String(matches) }, text: banner }),
    drop ? el('p', { class: 'note', text: `Drop #${drop.id} · player ${drop.playerId} · room ${drop.room} · bet ${formatAmount(drop.bet)} · nonce ${drop.nonce} · client seed “${drop.clientSeed}” · ${drop.status} · created ${drop.createdAt}${drop.serverSeed ? '' : ' · server seed not revealed (the chain from the commitment is checked by the server only)'}` }) : null,
    el('div', { class: 'table-wrap' },
      el('table', { class: 'compare' },
        el('thead', {}, el('tr', {}, el('th', { text: 'field' }), el('th', { text: 'stored' }), el('th', { text: 'server re-sim' }), el('th', { text: 'browser' }), el('th', { text: '' }))),
        el('tbody', {}, ...rows.map((r) => el('tr', {},
          el('td', { text: r.field }), cell(r.stored, r.field), cell(r.server, r.field), cell(r.browser, r.field),
          el('td', { class: r.agree === null ? '' : r.agree ? 'ok' : 'bad', text: r.agree === null ? '' : r.agree ? '✓' : '✗' })))))),
    recorded && recorded.length > 1 ? el('p', { class: 'note', text: `Stored drops with these seeds: ${recorded.map((r) => `#${r.id} (${r.matches ? 'matches' : 'differs'})`).join(', ')}` }) : null
  )
  return result
}

/** A compared value as the operator reads it: amounts as amounts (exact), multipliers with ×, long hex shortened. @param {any} value @param {string} [field] */
function format (value, field) {
  if (value === null || value === undefined) return '–'
  if (field === 'payout' || field === 'bet') return exactAmount(value)
  if (field === 'multiplier') return exactMultiplier(value)
  if (typeof value === 'string' && value.length > 24) return shortHex(value, 10)
  return String(value)
}

function say (text, kind = 'info') {
  const line = byId('lookup-message')
  line.textContent = text
  line.dataset.kind = kind
}

function showReplayState (p) {
  byId('play').textContent = p.playing ? '❚❚ Pause' : '▶ Play'
  const scrub = byId('scrub')
  scrub.max = String(p.ticks)
  scrub.value = String(Math.round(p.position))
  byId('tick-readout').textContent = p.trajectory ? `tick ${p.tick} / ${p.ticks}${p.tick >= p.ticks ? ` · bucket ${p.bucket}` : ''}` : 'no drop loaded'
}

// ---- player's drops -----------------------------------------------------------

/** The player list's date filter: local days, from the start of `from` to the end of `to` (ISO, for ?from=&to=). */
function dateRange () {
  const day = (id) => byId(id).value
  const start = (value) => (value ? new Date(`${value}T00:00:00`) : null)
  const from = start(day('player-from'))
  const toDay = start(day('player-to'))
  const to = toDay ? new Date(toDay.getTime() + 86_400_000 - 1) : null
  return { from: from?.toISOString(), to: to?.toISOString() }
}

async function listPlayer (playerId) {
  if (!requireToken()) return
  const body = byId('player-drops')
  const totals = byId('player-totals')
  const note = (text) => { body.replaceChildren(el('tr', {}, el('td', { colspan: 8, class: 'note', text }))); totals.replaceChildren() }
  try {
    const { drops } = await operatorGet(`/api/audit/drops${query({ player: playerId, limit: 200, ...dateRange() })}`)
    body.replaceChildren(...drops.map((d) => el('tr', { class: 'clickable', dataset: { dropId: String(d.id) }, title: 'look up and replay', onclick: () => lookupById(d.id) },
      el('td', { text: `#${d.id}` }), el('td', { text: d.room }), el('td', { class: 'num', text: formatAmount(d.bet) }),
      el('td', { class: 'num', text: d.multiplier === null ? '–' : formatMultiplier(d.multiplier), title: multiplierTitle(d.multiplier) }),
      el('td', { class: 'num col-bucket', text: d.bucket ?? '–' }),
      el('td', { class: 'num', text: formatAmount(d.payout), title: amountTitle(d.payout) }),
      el('td', { class: 'col-status', text: d.status }),
      el('td', { class: 'created', text: formatLocalTime(d.createdAt), title: `${d.createdAt} (UTC)` }))))
    if (drops.length === 0) return note('No drops for this player in these dates.')
    const settled = drops.filter((d) => d.status === 'settled')
    const betMilli = drops.reduce((sum, d) => sum + toMilli(d.bet), 0)
    const settledBetMilli = settled.reduce((sum, d) => sum + toMilli(d.bet), 0)
    const paidMilli = settled.reduce((sum, d) => sum + toMilli(d.payout), 0)
    const rtp = settledBetMilli > 0 ? `${(paidMilli / settledBetMilli * 100).toFixed(2)}%` : '–'
    state.playerTotals = { drops: drops.length, settled: settled.length, bet: toCredits(betMilli), payout: toCredits(paidMilli), rtp }
    // The RTP goes with the settled count at the end, where the text may wrap: in the × column it set
    // that column's width, and a big RTP (a 29× on 8 rows) pushed the table past a phone's width.
    totals.replaceChildren(el('tr', {},
      el('th', { colspan: 2, text: `${drops.length} drop${drops.length === 1 ? '' : 's'}${drops.length === 200 ? ' (the latest 200)' : ''}` }),
      el('th', { class: 'num', text: formatAmount(toCredits(betMilli)), title: amountTitle(toCredits(betMilli)) }),
      el('th'),
      el('th', { class: 'col-bucket' }),
      el('th', { class: 'num', text: formatAmount(toCredits(paidMilli)), title: amountTitle(toCredits(paidMilli)) }),
      el('th', { colspan: 2, class: 'note', text: `${settled.length} settled, RTP ${rtp}` })))
  } catch (error) {
    note(error.message)
  }
}

/** The player's whole history (GET /api/audit/export, JSON lines), saved as a file. */
async function exportPlayer (playerId) {
  if (!requireToken()) return
  const message = byId('player-message')
  message.textContent = `Exporting the drops of ${playerId}…`
  let response
  try {
    response = await fetch(`/api/audit/export${query({ player: playerId, format: 'ndjson' })}`, { headers: { authorization: `Bearer ${state.token}` }, cache: 'no-store' })
  } catch (error) {
    message.textContent = `Export failed: ${error.message}`
    return
  }
  if (!response.ok) {
    const reply = await response.json().catch(() => null)
    message.textContent = `Export failed: ${reply?.message ?? response.statusText}`
    return
  }
  const blob = await response.blob()
  const lines = (await blob.text()).split('\n').filter((line) => line !== '').length
  state.lastExport = { player: playerId, lines, bytes: blob.size }
  const link = el('a', { href: URL.createObjectURL(blob), download: `drops-${playerId.replace(/[^\w.-]/g, '_')}.ndjson` })
  document.body.append(link)
  link.click()
  link.remove()
  setTimeout(() => URL.revokeObjectURL(link.href), 60_000)
  message.textContent = `Exported ${lines} drop${lines === 1 ? '' : 's'} of ${playerId} (${formatAmount(blob.size)} bytes).`
}

// ---- room statistics ----------------------------------------------------------

async function showStats (room) {
  if (!requireToken()) return
  if (state.stats.room !== room) {
    state.stats.room = room
    state.stats.samples = []
    state.stats.history = null
  }
  clearTimeout(state.stats.timer)
  try {
    const stats = await operatorGet(`/api/audit/rooms/${room}/stats`)
    if (state.stats.room !== room) return
    if (state.stats.history === null) {
      state.stats.history = await roomHistory(room, stats)
      if (state.stats.room !== room) return
      state.stats.samples = state.stats.history.samples.slice()
    }
    state.stats.last = stats
    renderStats(stats)
  } catch (error) {
    byId('stats').replaceChildren(el('p', { class: 'note', text: error.message }))
  }
  if (state.token && state.stats.room === room) state.stats.timer = setTimeout(() => showStats(room), STATS_REFRESH_MS)
}

/**
 * The room's measured RTP as it grew, from its recorded drops (GET
 * /api/audit/drops?room=…, newest first, paged), so the chart of a quiet
 * room starts with its history instead of empty: its latest
 * HISTORY_DROPS settled drops under the room's engine version, oldest
 * first, as HISTORY_POINTS samples of the running RTP with its 95% band.
 */
async function roomHistory (room, stats) {
  const drops = []
  let before
  while (drops.length < HISTORY_DROPS) {
    const page = await operatorGet(`/api/audit/drops${query({ room, limit: HISTORY_PAGE, before })}`).catch(() => ({ drops: [] }))
    drops.push(...page.drops)
    if (page.drops.length < HISTORY_PAGE) break
    before = page.drops[page.drops.length - 1].id
  }
  const settled = drops.filter((d) => d.status === 'settled' && d.engineVersion === stats.engineVersion && d.bucket !== null).sort((p, q) => p.id - q.id)
  // Drops older than those loaded still count towards the total on the x axis.
  const earlier = Math.max(0, stats.settled - settled.length)
  const counts = new Array(stats.multipliers.length).fill(0)
  const samples = []
  const every = Math.max(1, Math.ceil(settled.length / HISTORY_POINTS))
  settled.forEach((drop, i) => {
    counts[drop.bucket]++
    if ((i + 1) % every !== 0 && i !== settled.length - 1) return
    const s = rtpStatistics(counts, stats.multipliers)
    samples.push({ drops: earlier + s.drops, rtp: s.rtp, low: s.ci95[0], high: s.ci95[1] })
  })
  return { loaded: settled.length, samples }
}

function stopStats () {
  clearTimeout(state.stats.timer)
  state.stats.room = null
}

function renderStats (stats) {
  const perDrop = rtpStatistics(stats.bucketCounts, stats.multipliers)
  const calibration = calibrationOf(stats.rows, stats.engineVersion)
  const calibrated = calibration.rtp[stats.risk]
  const samples = state.stats.samples
  if (samples.length === 0 || samples[samples.length - 1].drops !== perDrop.drops) {
    samples.push({ drops: perDrop.drops, rtp: perDrop.rtp, low: perDrop.ci95[0], high: perDrop.ci95[1] })
  }
  const percent = (v) => (v === null || !Number.isFinite(v) ? '–' : `${(v * 100).toFixed(2)}%`)
  const live = stats.live ? `${stats.live.players} player(s) connected, ${stats.live.ballsInFlight} ball(s) in flight, tick ${stats.live.tick}` : 'room not open right now'
  byId('stats').replaceChildren(
    el('p', { class: 'stat-line', id: 'stats-summary', dataset: { settled: String(stats.settled) }, text: `${stats.room}: ${stats.settled} settled, ${stats.inFlight} in flight · ${live}` }),
    el('p', { class: 'stat-line', text: `Wagered ${formatAmount(stats.totalBet)}, paid ${formatAmount(stats.totalPayout)} → RTP ${percent(stats.rtp)} of money wagered` }),
    el('p', { class: 'stat-line', text: `Mean multiplier per drop ${percent(perDrop.rtp)} (95% CI ${percent(perDrop.ci95[0])} – ${percent(perDrop.ci95[1])}) · calibrated ${percent(calibrated)} on ${calibration.drops.toLocaleString('en-US')} simulated drops (engine ${stats.engineVersion})` }),
    bucketChart(stats.bucketCounts, calibration.bucketCounts),
    legend([['measured share per bucket', CHART_COLORS.measured], ['calibrated share', CHART_COLORS.calibrated]]),
    rtpChart(samples, calibrated),
    legend([['measured RTP per drop, 95% band', CHART_COLORS.measured], ['calibrated RTP', CHART_COLORS.calibrated]])
  )
}

// ---- set-up -------------------------------------------------------------------

function setUp () {
  for (const id of ['seed-rows', 'stats-rows']) {
    const select = byId(id)
    for (let r = MIN_ROWS; r <= MAX_ROWS; r++) select.append(el('option', { value: String(r), text: String(r), selected: r === 16 }))
  }
  for (const version of ENGINE_VERSIONS) byId('seed-engine').append(el('option', { value: version, text: version, selected: version === ENGINE_VERSION }))
  byId('login-form').addEventListener('submit', (event) => {
    event.preventDefault()
    const token = byId('token').value.trim()
    if (token) signIn(token)
  })
  byId('sign-out').addEventListener('click', signOut)
  byId('id-form').addEventListener('submit', (event) => {
    event.preventDefault()
    const id = Number(byId('drop-id').value)
    if (Number.isSafeInteger(id) && id > 0) lookupById(id)
  })
  byId('seeds-form').addEventListener('submit', (event) => {
    event.preventDefault()
    const nonce = Number(byId('seed-nonce').value)
    const serverSeed = byId('seed-server').value
    const clientSeed = byId('seed-client').value
    if (!serverSeed || !clientSeed || !Number.isSafeInteger(nonce) || nonce < 0) {
      say('Enter a server seed, a client seed and a nonce.', 'error')
      return
    }
    lookupBySeeds({ serverSeed, clientSeed, nonce, rows: Number(byId('seed-rows').value), risk: byId('seed-risk').value, engineVersion: byId('seed-engine').value })
  })
  byId('player-form').addEventListener('submit', (event) => {
    event.preventDefault()
    const id = byId('player-id').value.trim()
    if (id) listPlayer(id)
  })
  byId('player-export').addEventListener('click', () => {
    const id = byId('player-id').value.trim()
    if (id) exportPlayer(id)
    else byId('player-message').textContent = 'Enter a player id to export.'
  })
  byId('stats-form').addEventListener('submit', (event) => {
    event.preventDefault()
    showStats(`${byId('stats-rows').value}-${byId('stats-risk').value}`)
  })
  byId('play').addEventListener('click', () => player.toggle())
  byId('step-back').addEventListener('click', () => player.step(-1))
  byId('step-forward').addEventListener('click', () => player.step(1))
  byId('speed').addEventListener('change', (event) => player.setSpeed(Number(event.target.value)))
  byId('scrub').addEventListener('input', (event) => { player.pause(); player.seek(Number(event.target.value)) })
  // Space: play/pause; arrows: one tick (with Shift: ten).
  document.addEventListener('keydown', (event) => {
    const target = event.target
    if (!player.trajectory || (target instanceof HTMLElement && ['INPUT', 'TEXTAREA', 'SELECT', 'BUTTON'].includes(target.tagName))) return
    if (event.code === 'Space') player.toggle()
    else if (event.code === 'ArrowLeft' || event.code === 'ArrowRight') player.step((event.code === 'ArrowLeft' ? -1 : 1) * (event.shiftKey ? 10 : 1))
    else return
    event.preventDefault()
  })
  byId('footer-stats').textContent = `engines ${ENGINE_VERSIONS.join(', ')} (each drop replays under its own) · everything on this page is re-simulated in your browser`
  // An empty board until a drop is loaded.
  renderer.setBoard(createBoard({ rows: 16, risk: 'medium' }))
  renderer.draw([], performance.now())
}

window.__audit = {
  get signedIn () { return state.signedIn },
  get lookups () { return state.lookups },
  get replay () { return { tick: player.tick, ticks: player.ticks, playing: player.playing, bucket: player.bucket } },
  get stats () { return state.stats.last },
  /** the RTP chart's points, the room's history first */
  get rtpSamples () { return state.stats.samples.map((s) => ({ ...s })) },
  get playerTotals () { return state.playerTotals ?? null },
  get lastExport () { return state.lastExport ?? null },
  get historyLoaded () { return state.stats.history ? state.stats.history.loaded : null },
  get frames () { return renderer.frames },
  lookupById,
  lookupBySeeds
}

setUp()
if (state.token) signIn(state.token)
else showAuth(false, 'Enter the operator token (the server logs it at start when OPERATOR_TOKEN is not set).')
