import Ajv from 'ajv'

/**
 * How every HTTP route's request schema is checked (app.setValidatorCompiler):
 * - querystring, params and headers arrive as text, so their numbers and
 *   booleans are coerced; the body is JSON and is taken as sent: a number
 *   where a string belongs is refused, as the WebSocket refuses it, never
 *   turned into "123";
 * - every `type: "integer"` is also a safe integer: Ajv's coercion turns
 *   "1e400" into Infinity, which its integer type and its minimum and maximum
 *   accept, so each integer schema gets the `safeInteger` keyword here
 *   (no route has to remember it);
 * - extra properties are an error, never silently dropped.
 * @returns {(route: { schema: object, httpPart?: string }) => (data: any) => boolean}
 */
export function requestValidatorCompiler () {
  const coercing = newAjv({ coerceTypes: 'array' })
  const asSent = newAjv({ coerceTypes: false })
  return ({ schema, httpPart }) => httpPart === 'body'
    ? asSent.compile(withSafeIntegers(schema))
    : decimalNumbersOnly(schema, coercing.compile(withSafeIntegers(schema)))
}

/** A number as a person writes it in decimal (exponent allowed): not 0x10, 0o20, 0b10000. */
const DECIMAL = /^\s*[-+]?(\d+\.?\d*|\.\d+)(e[-+]?\d+)?\s*$/i

/**
 * Ajv coerces text to a number with Number(), which reads "0x10" as 16:
 * before it does, each numeric property of a querystring or params object
 * given as text must be written in decimal.
 * @param {any} schema @param {import('ajv').ValidateFunction} validate
 */
function decimalNumbersOnly (schema, validate) {
  const numeric = Object.entries(schema?.properties ?? {})
    .filter(([, property]) => [property.type].flat().some((type) => type === 'integer' || type === 'number'))
    .map(([name]) => name)
  if (numeric.length === 0) return validate
  function decimalThenSchema (data) {
    for (const name of numeric) {
      const value = data?.[name]
      const texts = Array.isArray(value) ? value : [value]
      if (texts.some((text) => typeof text === 'string' && !DECIMAL.test(text))) {
        decimalThenSchema.errors = [{ instancePath: `/${name}`, schemaPath: '#/decimal', keyword: 'decimal', params: {}, message: 'must be a number written in decimal' }]
        return false
      }
    }
    const valid = validate(data)
    decimalThenSchema.errors = validate.errors
    return valid
  }
  return decimalThenSchema
}

function newAjv ({ coerceTypes }) {
  const ajv = new Ajv({ coerceTypes, useDefaults: true, removeAdditional: false, allErrors: false, strict: false })
  ajv.addKeyword({
    keyword: 'safeInteger',
    type: 'number',
    schemaType: 'boolean',
    errors: true,
    validate: function safeInteger (wanted, data) {
      if (!wanted || Number.isSafeInteger(data)) return true
      safeInteger.errors = [{ keyword: 'safeInteger', params: {}, message: `must be a whole number from ${-Number.MAX_SAFE_INTEGER} to ${Number.MAX_SAFE_INTEGER}` }]
      return false
    }
  })
  return ajv
}

/** A copy of `schema` with `safeInteger: true` beside every integer type. @param {any} schema */
export function withSafeIntegers (schema) {
  if (Array.isArray(schema)) return schema.map(withSafeIntegers)
  if (!schema || typeof schema !== 'object') return schema
  const copy = {}
  for (const [key, value] of Object.entries(schema)) copy[key] = key === 'enum' || key === 'const' || key === 'default' ? value : withSafeIntegers(value)
  const types = Array.isArray(schema.type) ? schema.type : [schema.type]
  if (types.includes('integer')) copy.safeInteger = true
  return copy
}
