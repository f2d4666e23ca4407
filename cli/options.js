import { parseArgs } from 'node:util'
import { UsageError } from './usage-error.js'
import { MIN_ROWS, MAX_ROWS, RISKS } from '../engine/board.js'
import { ENGINE_VERSION, ENGINE_VERSIONS, isEngineVersion } from '../engine/version.js'

/**
 * Parses argv against `options` (node:util parseArgs), turning its errors
 * into UsageErrors.
 */
export function parseOptions (argv, options) {
  try {
    return parseArgs({ args: argv, options, strict: true, allowPositionals: false }).values
  } catch (error) {
    throw new UsageError(error.message)
  }
}

/** @param {string | undefined} text @param {string} name @param {{ min?: number, max?: number }} [range] */
export function integerOption (text, name, { min = 0, max = Number.MAX_SAFE_INTEGER } = {}) {
  if (text === undefined) throw new UsageError(`--${name} is required`)
  if (!/^\d+$/.test(text)) throw new UsageError(`--${name} must be a whole number, got "${text}"`)
  const value = Number(text)
  if (!Number.isSafeInteger(value) || value < min || value > max) {
    throw new UsageError(`--${name} must be between ${min} and ${max}, got ${text}`)
  }
  return value
}

export function rowsOption (text) {
  return integerOption(text ?? '16', 'rows', { min: MIN_ROWS, max: MAX_ROWS })
}

export function riskOption (text) {
  const risk = text ?? 'medium'
  if (!RISKS.includes(risk)) throw new UsageError(`--risk must be one of ${RISKS.join(', ')}, got "${risk}"`)
  return risk
}

export function requiredString (text, name) {
  if (text === undefined || text === '') throw new UsageError(`--${name} is required`)
  return text
}

/** --engine-version: one of the shipped versions, default the newest. */
export function engineVersionOption (text) {
  const version = text ?? ENGINE_VERSION
  if (!isEngineVersion(version)) throw new UsageError(`--engine-version must be one of ${ENGINE_VERSIONS.join(', ')}, got "${version}"`)
  return version
}
