/**
 * What a client may send, one module for the server (which checks every
 * message against these schemas before any handler sees it) and the
 * browser (served at /protocol/). Unknown properties are refused. An
 * optional `ref` (a string of up to 64 characters or an integer) is echoed
 * in the direct reply, so a client can match replies to its requests.
 */

/** Client seeds: 1 to 64 printable ASCII characters (space to tilde). */
export const CLIENT_SEED_PATTERN = '^[\\x20-\\x7e]{1,64}$'

/**
 * How a socket in a room learns what happens in it, chosen in `join`:
 * "snapshots" (the default) gets the balls' positions 1–60 times a second
 * (protocol/snapshot-codec.js); "seeds" gets only the drops, as binary
 * events, and simulates the balls itself (protocol/drop-events-codec.js).
 * Any other value is refused with E_BAD_DELIVERY.
 */
export const DELIVERY_MODES = Object.freeze(['snapshots', 'seeds'])
export const DEFAULT_DELIVERY = 'snapshots'

const ref = { anyOf: [{ type: 'string', maxLength: 64 }, { type: 'integer' }] }

/**
 * JSON schemas of every client → server message, by type.
 * @param {{ minBet: number, maxBet: number }} limits the server's bet limits (sent in `welcome`)
 */
export function clientMessageSchemas ({ minBet, maxBet }) {
  const message = (type, properties = {}, required = []) => ({
    type: 'object',
    properties: { type: { const: type }, ref, ...properties },
    required: ['type', ...required],
    additionalProperties: false
  })
  return {
    join: message('join', { room: { type: 'string', maxLength: 32 }, delivery: { enum: DELIVERY_MODES } }, ['room']),
    leave: message('leave'),
    drop: message('drop', {
      bet: { type: 'integer', minimum: minBet, maximum: maxBet },
      clientSeed: { type: 'string', pattern: CLIENT_SEED_PATTERN }
    }, ['bet']),
    ping: message('ping')
  }
}
