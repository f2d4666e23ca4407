import { ENGINE_1_0_0 } from './versions/engine-1.0.0.js'
import { ENGINE_2_0_0 } from './versions/engine-2.0.0.js'

/**
 * Engine versions. A version names everything that can change the outcome
 * of a drop: solver, board geometry, materials, release conditions and
 * multiplier tables. Every version ever shipped stays here, runnable, so a
 * drop verifies under the version it was decided under for as long as the
 * ledger keeps it; new drops use the newest. Never edit a shipped version:
 * add the next one (engine/versions/engine-X.Y.Z.js) and append it here.
 */
const RULES = [ENGINE_1_0_0, ENGINE_2_0_0]

/** Every shipped engine version, oldest first. */
export const ENGINE_VERSIONS = Object.freeze(RULES.map((rules) => rules.version))

/** The newest engine version: the one new drops are decided under. */
export const ENGINE_VERSION = ENGINE_VERSIONS[ENGINE_VERSIONS.length - 1]

/** Thrown for a version string that names no shipped engine. */
export class UnknownEngineVersionError extends RangeError {
  /** @param {unknown} version */
  constructor (version) {
    super(`unknown engine version ${JSON.stringify(version)}: this engine runs ${ENGINE_VERSIONS.join(', ')}`)
    this.name = 'UnknownEngineVersionError'
    this.code = 'E_UNKNOWN_ENGINE_VERSION'
    this.version = version
  }
}

const byVersion = new Map(RULES.map((rules) => [rules.version, deepFreeze(rules)]))

/** @param {unknown} version */
export function isEngineVersion (version) {
  return typeof version === 'string' && byVersion.has(version)
}

/**
 * The rules of one engine version (frozen).
 * @param {string} [version] default: the newest
 * @throws {UnknownEngineVersionError}
 */
export function engineRules (version = ENGINE_VERSION) {
  const rules = typeof version === 'string' ? byVersion.get(version) : undefined
  if (!rules) throw new UnknownEngineVersionError(version)
  return rules
}

function deepFreeze (value) {
  if (value && typeof value === 'object' && !Object.isFrozen(value)) {
    Object.freeze(value)
    for (const key of Object.keys(value)) deepFreeze(value[key])
  }
  return value
}
