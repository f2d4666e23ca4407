import { createBoard, simulateDrop } from '/engine/index.js'
import { apiRequest } from './api.js'
import { checkFairness } from './fair-check.js'

/**
 * Another player's drop, verified on demand in this browser. In seeds
 * mode the page hears of other players' drops only as compact events and
 * their flights are covered by the room's flight hash; a player who wants
 * more asks for one drop's public facts (GET /api/public/drops/:id) and
 * the page checks them with its own engine, under the drop's engine
 * version: once the drop's server seed is revealed (the record has
 * `serverSeed`), the whole chain (fair-check.js: commitment, drop seed,
 * outcome); before that, the outcome of its drop seed: bucket, ticks and
 * the hash of the ball's final state must be what the server recorded.
 */

/**
 * @typedef {object} PublicDropCheck
 * @property {number} dropId
 * @property {'chain' | 'outcome' | 'unsettled'} kind what could be checked: the seed chain (server seed revealed), the outcome of the drop seed, nothing yet (not settled)
 * @property {boolean} ok every check made passed
 * @property {Record<string, boolean | null>} checks each link against the record (null: nothing recorded to compare)
 * @property {object} record the server's public facts
 * @property {{ bucket: number, ticks: number, stateHash: string } | null} local this page's outcome
 */

/**
 * @param {number} dropId
 * @param {{ request?: typeof apiRequest, announcedSeed?: string | null }} [options]
 *   announcedSeed: the drop seed the room announced, if the page has it (compared with the record's)
 * @returns {Promise<PublicDropCheck>}
 */
export async function checkPublicDrop (dropId, { request = apiRequest, announcedSeed = null } = {}) {
  const record = await request('GET', `/api/public/drops/${dropId}`)
  const announced = announcedSeed === null ? null : announcedSeed === record.dropSeed
  if (record.status !== 'settled') return { dropId, kind: 'unsettled', ok: announced !== false, checks: { announced }, record, local: null }
  if (record.serverSeed) {
    const fair = await checkFairness({ serverSeed: record.serverSeed, clientSeed: record.clientSeed, nonce: record.nonce, rows: record.rows, risk: record.risk, engineVersion: record.engineVersion }, record)
    const checks = { ...fair.checks, announced }
    return { dropId, kind: 'chain', ok: fair.ok && announced !== false, checks, record, local: { bucket: fair.bucket, ticks: fair.ticks, stateHash: fair.stateHash } }
  }
  const outcome = simulateDrop(createBoard({ rows: record.rows, risk: record.risk, engineVersion: record.engineVersion }), record.dropSeed)
  const checks = { bucket: outcome.bucket === record.bucket, ticks: outcome.ticks === record.ticks, stateHash: outcome.stateHash === record.stateHash, announced }
  return { dropId, kind: 'outcome', ok: Object.values(checks).every((check) => check !== false), checks, record, local: { bucket: outcome.bucket, ticks: outcome.ticks, stateHash: outcome.stateHash } }
}

/** What the feed shows for a check. @param {PublicDropCheck} check */
export function describeCheck (check) {
  const { record, local } = check
  if (check.kind === 'unsettled') return check.ok ? `Drop ${check.dropId} has not landed yet: verify it again when it has.` : `✗ Drop ${check.dropId}: its recorded drop seed is not the one the room announced.`
  const failed = Object.entries(check.checks).filter(([, passed]) => passed === false).map(([name]) => name)
  if (!check.ok) return `✗ Drop ${check.dropId} does NOT verify in this browser (${failed.join(', ')}): the server recorded bucket ${record.bucket}, ${record.ticks} ticks, state ${record.stateHash}; this page's engine gives bucket ${local.bucket}, ${local.ticks} ticks, state ${local.stateHash}.`
  const what = check.kind === 'chain'
    ? 'server seed, its commitment, the drop seed and the outcome'
    : 'the outcome of its drop seed (its server seed is not revealed yet)'
  return `✓ Verified in this browser: ${what}. Bucket ${local.bucket}, ${local.ticks} ticks, state ${local.stateHash}.`
}
