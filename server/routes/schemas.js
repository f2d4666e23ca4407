import { CLIENT_SEED_PATTERN } from '../fairness/seeds.js'

/**
 * Shared JSON schemas for HTTP routes. Response schemas double as an
 * allow-list: fastify serialises only the listed properties, so nothing
 * (an active server seed, a token hash) can leak by accident.
 */
export const errorReply = {
  type: 'object',
  properties: { code: { type: 'string' }, message: { type: 'string' } },
  required: ['code', 'message']
}

export const clientSeed = { type: 'string', pattern: CLIENT_SEED_PATTERN }

const nullable = (type) => ({ type: [type, 'null'] })

export const dropRecord = {
  type: 'object',
  properties: {
    id: { type: 'integer' },
    playerId: { type: 'string' },
    room: { type: 'string' },
    rows: { type: 'integer' },
    risk: { type: 'string' },
    engineVersion: { type: 'string' },
    serverSeedHash: { type: 'string' },
    serverSeed: nullable('string'),
    clientSeed: { type: 'string' },
    nonce: { type: 'integer' },
    dropSeed: { type: 'string' },
    bet: { type: 'integer' },
    bucket: nullable('integer'),
    multiplier: nullable('number'),
    payout: nullable('number'),
    payoutRule: { type: 'integer', description: 'how the payout was computed (protocol/payout.js): 1 floor to whole credits (before migration 2), 2 exact' },
    startTick: { type: 'integer' },
    ticks: nullable('integer'),
    stateHash: nullable('string'),
    status: { type: 'string', enum: ['in_flight', 'settled'] },
    createdAt: { type: 'string' },
    settledAt: nullable('string')
  }
}

export const dropList = {
  type: 'object',
  properties: { drops: { type: 'array', items: dropRecord } }
}

/** Standard error replies for a route, by status. */
export function errors (...statuses) {
  return Object.fromEntries(statuses.map((status) => [status, errorReply]))
}

/** A timestamp filter: ISO 8601 date/time or milliseconds since the epoch. */
export const timeParam = { type: 'string', maxLength: 40 }

/**
 * ISO 8601 as Date.parse reads it: a date, optionally a time, optionally
 * an offset. Anything else is refused before Date.parse sees it, which
 * would take "1.5" or "Dec 2" as some date.
 */
const ISO_TIME = /^[+-]?\d{4,6}-\d{2}-\d{2}(T\d{2}:\d{2}(:\d{2}(\.\d{1,9})?)?(Z|[+-]\d{2}:\d{2})?)?$/i

/** @param {string | undefined} value @returns {number | undefined} ms */
export function parseTime (value) {
  if (value === undefined) return undefined
  const ms = /^\d+$/.test(value) ? Number(value) : ISO_TIME.test(value) ? Date.parse(value) : NaN
  // Beyond ±8.64e15 ms is no date (and overflows the database's types).
  return Number.isFinite(ms) && Math.abs(ms) <= 8.64e15 ? ms : NaN
}
