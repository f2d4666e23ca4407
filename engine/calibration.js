import { engineRules, ENGINE_VERSION } from './version.js'

/**
 * What the multiplier tables of one board were calibrated on: the number of
 * simulated drops, their bucket counts and the RTP of each risk's table on
 * those drops. (1.0.0 calibrated every row count on the same number of
 * drops; later versions on as many as each board's variance needs.)
 * @param {number} rows @param {string} [engineVersion] default the newest
 * @returns {{ drops: number, bucketCounts: readonly number[], rtp: Readonly<Record<string, number>> } | null}
 */
export function calibrationOf (rows, engineVersion = ENGINE_VERSION) {
  const calibration = engineRules(engineVersion).calibration
  const bucketCounts = calibration?.bucketCounts?.[rows]
  if (!bucketCounts) return null
  const drops = typeof calibration.drops === 'number' ? calibration.drops : calibration.drops[rows]
  return { drops, bucketCounts, rtp: calibration.rtp[rows] }
}
