/**
 * Recorded-constant determinism test (Box2D style): fixed drop seeds on every
 * board must reproduce the bucket, tick count and exact final-state hash
 * recorded in tests/engine/fixtures/determinism-hashes.json under the current
 * ENGINE_VERSION. To re-record after an intentional engine change, bump
 * ENGINE_VERSION in engine/version.js, then run
 *   node tests/engine/fixtures/record-determinism-hashes.js
 */
import { describe, it, expect } from 'vitest'
import { readFileSync } from 'node:fs'
import { createBoard, simulateDrop, ENGINE_VERSION } from '../../engine/index.js'
import { ALL_ROWS, ALL_RISKS } from '../helpers/determinism-inputs.js'

const fixture = JSON.parse(readFileSync(new URL('./fixtures/determinism-hashes.json', import.meta.url), 'utf8'))
const RERECORD = 'node tests/engine/fixtures/record-determinism-hashes.js'

describe('recorded determinism fixtures', () => {
  it('cover every board', () => {
    expect(new Set(fixture.drops.map((d) => `${d.rows}:${d.risk}`)).size).toBe(ALL_ROWS.length * ALL_RISKS.length)
  })

  it('were recorded under the current ENGINE_VERSION', () => {
    expect(
      fixture.engineVersion,
      `ENGINE_VERSION is ${ENGINE_VERSION} but the fixtures were recorded under ${fixture.engineVersion}: re-record them with \`${RERECORD}\``
    ).toBe(ENGINE_VERSION)
  })

  it('are reproduced bit for bit by the engine', () => {
    const mismatches = []
    for (const { rows, risk, dropSeed, bucket, ticks, stateHash } of fixture.drops) {
      const got = simulateDrop(createBoard({ rows, risk }), dropSeed)
      if (got.bucket !== bucket || got.ticks !== ticks || got.stateHash !== stateHash) {
        mismatches.push({ rows, risk, dropSeed, recorded: { bucket, ticks, stateHash }, now: { bucket: got.bucket, ticks: got.ticks, stateHash: got.stateHash } })
      }
    }
    const hint = fixture.engineVersion === ENGINE_VERSION
      ? `The engine's outcome changed but ENGINE_VERSION is still ${ENGINE_VERSION}. If the change is intended, bump ENGINE_VERSION in engine/version.js and re-record with \`${RERECORD}\`; otherwise this is a determinism regression.`
      : `Fixtures are from engine ${fixture.engineVersion}, the engine is ${ENGINE_VERSION}: re-record with \`${RERECORD}\`.`
    expect(mismatches, `${mismatches.length} of ${fixture.drops.length} recorded drops changed. ${hint}`).toEqual([])
  })
})
