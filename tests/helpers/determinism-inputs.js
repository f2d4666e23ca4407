import { createHmac } from 'node:crypto'
import { ENGINE_VERSIONS } from '../../engine/index.js'

/** Rows and risks every board of the game can have. */
export const ALL_ROWS = [8, 9, 10, 11, 12, 13, 14, 15, 16]
export const ALL_RISKS = ['low', 'medium', 'high']

/**
 * Fixed drops for determinism tests (Node only; other runtimes receive the
 * result as data) under one engine version: drop i uses
 *   dropSeed = HMAC-SHA256(key = `key`, message = `client:${i}`) in hex,
 * and cycles through all 27 boards, rows fastest:
 *   rows = 8 + i % 9, risk = ['low', 'medium', 'high'][floor(i / 9) % 3].
 * @param {number} count
 * @param {string} [key]
 * @param {string} engineVersion
 * @returns {{ rows: number, risk: string, engineVersion: string, dropSeed: string }[]}
 */
export function determinismDrops (count, key = 'cross-runtime', engineVersion) {
  if (!ENGINE_VERSIONS.includes(engineVersion)) throw new RangeError(`determinismDrops needs a shipped engine version, got ${engineVersion}`)
  const drops = []
  for (let i = 0; i < count; i++) {
    drops.push({
      rows: ALL_ROWS[i % ALL_ROWS.length],
      risk: ALL_RISKS[Math.floor(i / ALL_ROWS.length) % ALL_RISKS.length],
      engineVersion,
      dropSeed: createHmac('sha256', key).update(`client:${i}`).digest('hex')
    })
  }
  return drops
}

/** The same `count` drops under every shipped engine version, oldest version first. @param {number} count */
export function determinismDropsOfEveryVersion (count, key = 'cross-runtime') {
  return ENGINE_VERSIONS.flatMap((version) => determinismDrops(count, key, version))
}
