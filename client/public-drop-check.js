import { createBoard, simulateDrop } from '/engine/index.js'
import { apiRequest } from './api.js'
import { checkFairness } from './fair-check.js'
import { sharedDropPath, shareToken } from './share-link.js'

/**
 * Another player's drop, verified on demand in this browser. In seeds
 * mode the page hears of other players' drops only as compact events and
 * their flights are covered by the room's flight hash; a player who wants
 * more asks for the drop through its share link (GET /api/share/:id/:token),
 * whose token the page computes from the drop seed its room announced (no
 * other route serves another player's drop, so ids cannot be walked). The
 * page checks the record with its own engine, under the drop's engine
 * version: once the drop's server seed is revealed (the record has
 * `serverSeed`), the whole chain (fair-check.js: commitment, drop seed,
 * outcome); before that, the outcome of its drop seed: bucket, ticks and
 * the hash of the ball's final state must be what the server recorded.
 * A 404 means the server has no drop of that id with the announced seed.
 */

/**
 * @typedef {object} PublicDropCheck
 * @property {number} dropId
 * @property {'chain' | 'outcome' | 'unsettled' | 'unrecorded'} kind what could be checked: the seed chain (server seed revealed), the outcome of the drop seed, nothing yet (not settled), nothing (no drop with the announced seed)
 * @property {boolean} ok every check made passed
 * @property {Record<string, boolean | null>} checks each link against the record (null: nothing recorded to compare)
 * @property {object | null} record the shared drop (GET /api/share/:id/:token), null when there is none
 * @property {{ bucket: number, ticks: number, stateHash: string } | null} local this page's outcome
 */

/**
 * @param {{ dropId: number, dropSeed: string }} drop the drop and the seed its room announced
 * @param {{ request?: typeof apiRequest }} [options]
 * @returns {Promise<PublicDropCheck>}
 */
export async function checkPublicDrop ({ dropId, dropSeed }, { request = apiRequest } = {}) {
  let record
  try {
    record = await request('GET', sharedDropPath(dropId, await shareToken(dropSeed)))
  } catch (error) {
    if (error.code !== 'E_NOT_FOUND') throw error
    return { dropId, kind: 'unrecorded', ok: false, checks: { announced: false }, record: null, local: null }
  }
  const announced = record.id === dropId && record.dropSeed === dropSeed
  if (record.status !== 'settled') return { dropId, kind: 'unsettled', ok: announced, checks: { announced }, record, local: null }
  if (record.serverSeed) {
    const fair = await checkFairness({ serverSeed: record.serverSeed, clientSeed: record.clientSeed, nonce: record.nonce, rows: record.rows, risk: record.risk, engineVersion: record.engineVersion }, record)
    const checks = { ...fair.checks, announced }
    return { dropId, kind: 'chain', ok: fair.ok && announced, checks, record, local: { bucket: fair.bucket, ticks: fair.ticks, stateHash: fair.stateHash } }
  }
  const outcome = simulateDrop(createBoard({ rows: record.rows, risk: record.risk, engineVersion: record.engineVersion }), record.dropSeed)
  const checks = { bucket: outcome.bucket === record.bucket, ticks: outcome.ticks === record.ticks, stateHash: outcome.stateHash === record.stateHash, announced }
  return { dropId, kind: 'outcome', ok: Object.values(checks).every((check) => check !== false), checks, record, local: { bucket: outcome.bucket, ticks: outcome.ticks, stateHash: outcome.stateHash } }
}

/** What the feed shows for a check. @param {PublicDropCheck} check */
export function describeCheck (check) {
  const { record, local } = check
  if (check.kind === 'unrecorded') return `✗ Drop ${check.dropId}: the server has no drop ${check.dropId} with the seed the room announced.`
  if (check.kind === 'unsettled') return check.ok ? `Drop ${check.dropId} has not landed yet: verify it again when it has.` : `✗ Drop ${check.dropId}: its recorded drop seed is not the one the room announced.`
  const failed = Object.entries(check.checks).filter(([, passed]) => passed === false).map(([name]) => name)
  if (!check.ok) return `✗ Drop ${check.dropId} does NOT verify in this browser (${failed.join(', ')}): the server recorded bucket ${record.bucket}, ${record.ticks} ticks, state ${record.stateHash}; this page's engine gives bucket ${local.bucket}, ${local.ticks} ticks, state ${local.stateHash}.`
  const what = check.kind === 'chain'
    ? 'server seed, its commitment, the drop seed and the outcome'
    : 'the outcome of its drop seed (its server seed is not revealed yet)'
  return `✓ Verified in this browser: ${what}. Bucket ${local.bucket}, ${local.ticks} ticks, state ${local.stateHash}.`
}
