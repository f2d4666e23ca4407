/**
 * Recorded-constant determinism test (Box2D style), for every engine version
 * ever shipped: fixed drop seeds on every board must reproduce the bucket,
 * tick count and exact final-state hash recorded in
 * tests/engine/fixtures/engine-VERSION.json, and the 1,000 cross-runtime
 * drops the digest recorded there. A shipped version must verify forever:
 * if one of these fails, the engine changed an outcome it must not change.
 * A new version is recorded once with
 *   node tests/engine/fixtures/record-determinism-hashes.js --engine-version V
 */
import { describe, it, expect } from 'vitest'
import { existsSync, readdirSync, readFileSync } from 'node:fs'
import { createBoard, simulateDrop, ENGINE_VERSIONS } from '../../engine/index.js'
import { ALL_ROWS, ALL_RISKS, determinismDrops } from '../helpers/determinism-inputs.js'
import { runDeterminismProbe } from './fixtures/determinism-probe.js'
import { fixtureFile } from './fixtures/record-determinism-hashes.js'

const FIXTURES = new URL('./fixtures/', import.meta.url)

describe('recorded determinism fixtures', () => {
  it('exist for every shipped engine version, and no version was dropped', () => {
    const recorded = readdirSync(FIXTURES).map((name) => /^engine-(.+)\.json$/.exec(name)?.[1]).filter(Boolean)
    expect(recorded.sort()).toEqual([...ENGINE_VERSIONS].sort())
  })

  describe.each(ENGINE_VERSIONS)('engine %s', (version) => {
    const fixture = existsSync(fixtureFile(version)) ? JSON.parse(readFileSync(fixtureFile(version), 'utf8')) : null

    it('covers every board', () => {
      expect(fixture?.engineVersion).toBe(version)
      expect(new Set(fixture.drops.map((d) => `${d.rows}:${d.risk}`)).size).toBe(ALL_ROWS.length * ALL_RISKS.length)
    })

    it('reproduces every recorded drop bit for bit', () => {
      const mismatches = []
      for (const { rows, risk, dropSeed, bucket, ticks, stateHash } of fixture.drops) {
        const got = simulateDrop(createBoard({ rows, risk, engineVersion: version }), dropSeed)
        if (got.bucket !== bucket || got.ticks !== ticks || got.stateHash !== stateHash) {
          mismatches.push({ rows, risk, dropSeed, recorded: { bucket, ticks, stateHash }, now: { bucket: got.bucket, ticks: got.ticks, stateHash: got.stateHash } })
        }
      }
      expect(mismatches, `${mismatches.length} of ${fixture.drops.length} recorded drops of engine ${version} changed: a shipped version's outcomes must never change (a change needs a new ENGINE_VERSION)`).toEqual([])
    })

    it('reproduces the recorded digest of the 1,000 cross-runtime drops', () => {
      const { drops, key, digest } = fixture.crossRuntime
      expect(runDeterminismProbe(determinismDrops(drops, key, version)).digest).toBe(digest)
    })
  })
})
