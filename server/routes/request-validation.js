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
  return ({ schema, httpPart }) => (httpPart === 'body' ? asSent : coercing).compile(withSafeIntegers(schema))
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
