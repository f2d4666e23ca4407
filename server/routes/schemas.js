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

/**
 * The body of a POST that takes no options: absent (what the pages, the
 * k6 players and the scripts send) or `{}`; anything else is 400
 * E_BAD_REQUEST, so a misspelt option is never silently ignored.
 */
export const noOptionsBody = {
  type: ['object', 'null'],
  description: 'No options: send no body, or `{}`',
  properties: {},
  additionalProperties: false
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

/**
 * A timestamp filter: milliseconds since the epoch (up to 15 digits), or an
 * ISO 8601 date, or date and time (minutes, seconds and fractions optional;
 * `Z` or an offset). The pattern is the whole rule, so a client knows what is
 * accepted: every string it matches is a time parseTime reads (Date.parse takes
 * day 31 of any month, rolling over into the next).
 * ASCII digits spelt out: `\d` is wider than 0-9 in other regex engines.
 */
const ISO_DATE = '[0-9]{4}-(0[1-9]|1[0-2])-(0[1-9]|[12][0-9]|3[01])'
const ISO_TIME = 'T([01][0-9]|2[0-3]):[0-5][0-9](:[0-5][0-9](\\.[0-9]{1,9})?)?(Z|[+-]([01][0-9]|2[0-3]):[0-5][0-9])?'
export const TIME_PATTERN = `^([0-9]{1,15}|${ISO_DATE}(${ISO_TIME})?)$`
export const timeParam = { type: 'string', pattern: TIME_PATTERN, maxLength: 40, description: 'milliseconds since the epoch, or an ISO 8601 date or date-time (e.g. 2026-01-31 or 2026-01-31T12:00:00Z)' }

/** @param {string | undefined} value @returns {number | undefined} ms */
export function parseTime (value) {
  if (value === undefined) return undefined
  const ms = /^\d+$/.test(value) ? Number(value) : Date.parse(value)
  // Beyond ±8.64e15 ms is no date (and overflows the database's types).
  return Number.isFinite(ms) && Math.abs(ms) <= 8.64e15 ? ms : NaN
}
