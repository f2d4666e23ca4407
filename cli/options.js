import { UsageError } from './usage-error.js'
import { parseCommandLine } from './command-line.js'
import { MIN_ROWS, MAX_ROWS, RISKS } from '../engine/board.js'
import { ENGINE_VERSION, ENGINE_VERSIONS, isEngineVersion } from '../engine/version.js'

/**
 * Parses a command's argv against its `options` (node:util parseArgs, see
 * cli/command-line.js): every command also takes -h/--help (then the values
 * are `{ help: true }`); an unknown, repeated or value-less option is a
 * UsageError.
 */
export function parseOptions (argv, options) {
  return parseCommandLine(argv, { help: { type: 'boolean', short: 'h' }, ...options })
}

/** @param {string | undefined} text @param {string} name @param {{ min?: number, max?: number }} [range] */
export function integerOption (text, name, { min = 0, max = Number.MAX_SAFE_INTEGER } = {}) {
  if (text === undefined) throw new UsageError(`--${name} is required`)
  const value = Number(text)
  if (!/^\d+$/.test(text) || !Number.isSafeInteger(value) || value < min || value > max) {
    throw new UsageError(`--${name} must be a whole number from ${min} to ${max}, got "${text}"`)
  }
  return value
}

/** The options of a drop's seeds and board, shared by `verify` and `rtp`. */
export const SEED_AND_BOARD_OPTIONS = Object.freeze({
  'server-seed': { type: 'string' },
  'client-seed': { type: 'string' },
  rows: { type: 'string' },
  risk: { type: 'string' },
  'engine-version': { type: 'string' }
})

/** Their help lines (the seeds' lines differ per command). */
export const BOARD_OPTIONS_HELP = `  --rows N             rows of the board, ${MIN_ROWS} to ${MAX_ROWS} (default 16)
  --risk R             ${RISKS.join(', ')} (default medium)
  --engine-version V   ${ENGINE_VERSIONS.join(', ')} (default the newest)`

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
