import Ajv from 'ajv'
import { clientMessageSchemas } from '../../protocol/client-messages.js'
import { gameError } from '../errors.js'

export { clientMessageSchemas }

/** Which error code a schema failure on a given field is reported as. */
const FIELD_CODES = { '/bet': 'E_BAD_BET', '/clientSeed': 'E_BAD_SEED', '/room': 'E_UNKNOWN_ROOM', '/delivery': 'E_BAD_DELIVERY' }

/**
 * Compiles the schemas once; the returned function parses a text frame and
 * returns the message, or throws a GameError naming what is wrong.
 * @param {{ minBet: number, maxBet: number }} limits
 * @returns {(text: string) => { type: string, ref?: any, [key: string]: any }}
 */
export function createMessageParser (limits) {
  const ajv = new Ajv({ allErrors: false, strict: true })
  const validators = new Map(Object.entries(clientMessageSchemas(limits)).map(([type, schema]) => [type, ajv.compile(schema)]))
  return function parseClientMessage (text) {
    let message
    try {
      message = JSON.parse(text)
    } catch {
      throw gameError('E_BAD_MESSAGE', 'message is not valid JSON')
    }
    if (message === null || typeof message !== 'object' || Array.isArray(message) || typeof message.type !== 'string') {
      throw gameError('E_BAD_MESSAGE', 'message must be a JSON object with a string "type"')
    }
    const validate = validators.get(message.type)
    if (!validate) throw gameError('E_UNKNOWN_TYPE', `unknown message type ${JSON.stringify(message.type.slice(0, 32))}; known: ${[...validators.keys()].join(', ')}`, { ref: echoableRef(message.ref) })
    if (!validate(message)) {
      const [error] = validate.errors
      const code = FIELD_CODES[error.instancePath] ?? 'E_BAD_MESSAGE'
      const where = error.instancePath === '' ? message.type : `${message.type}${error.instancePath.replaceAll('/', '.')}`
      throw gameError(code, `${where} ${error.message}`, { ref: echoableRef(message.ref) })
    }
    return message
  }
}

/** A ref worth echoing back even when the rest of the message is wrong. */
function echoableRef (value) {
  if ((typeof value === 'string' && value.length <= 64) || Number.isSafeInteger(value)) return value
  return undefined
}
