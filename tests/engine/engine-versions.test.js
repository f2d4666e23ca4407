import { describe, it, expect } from 'vitest'
import { ENGINE_VERSION, ENGINE_VERSIONS, engineRules, isEngineVersion, UnknownEngineVersionError } from '../../engine/version.js'
import { createBoard, simulateDrop, verifyDrop, SOLVER, DropSimulator } from '../../engine/index.js'
import { calibrationOf } from '../../engine/calibration.js'

describe('engine versions', () => {
  it('lists every shipped version, oldest first, 1.0.0 among them, the newest the default', () => {
    expect(ENGINE_VERSIONS[0]).toBe('1.0.0')
    expect(ENGINE_VERSIONS).toContain('2.0.0')
    expect(ENGINE_VERSION).toBe(ENGINE_VERSIONS[ENGINE_VERSIONS.length - 1])
    expect(new Set(ENGINE_VERSIONS).size).toBe(ENGINE_VERSIONS.length)
  })

  it('keeps each version\'s rules frozen and addressable by its version string', () => {
    for (const version of ENGINE_VERSIONS) {
      const rules = engineRules(version)
      expect(rules.version).toBe(version)
      expect(Object.isFrozen(rules)).toBe(true)
      expect(Object.isFrozen(rules.geometry)).toBe(true)
      expect(Object.isFrozen(rules.multipliers[16].high)).toBe(true)
      expect(() => { rules.geometry.ballRadius = 1 }).toThrow(TypeError)
      // Each names the solver it was decided with; this engine runs it.
      expect(rules.solver).toEqual({ ...SOLVER })
    }
  })

  it('refuses a version that was never shipped with a named error', () => {
    for (const bad of ['0.9.0', '2.0', '', 'latest', undefined, null, 2, {}]) {
      if (bad === undefined) continue // undefined means the default (newest)
      expect(isEngineVersion(bad)).toBe(false)
      expect(() => engineRules(bad)).toThrow(UnknownEngineVersionError)
      expect(() => createBoard({ rows: 8, risk: 'low', engineVersion: bad })).toThrow(/unknown engine version/)
    }
    try {
      engineRules('9.9.9')
    } catch (error) {
      expect(error.code).toBe('E_UNKNOWN_ENGINE_VERSION')
      expect(error).toBeInstanceOf(RangeError)
      expect(error.message).toContain(ENGINE_VERSIONS.join(', '))
    }
  })

  it('decides the same seed differently under different versions (the version is part of the outcome)', () => {
    const seed = 'c0ffee'.repeat(10) + 'beef'
    const outcomes = ENGINE_VERSIONS.map((engineVersion) => simulateDrop(createBoard({ rows: 16, risk: 'high', engineVersion }), seed))
    expect(new Set(outcomes.map((o) => o.stateHash)).size).toBe(ENGINE_VERSIONS.length)
  })

  it('verifies a drop under the version asked for', async () => {
    const seeds = { serverSeed: 'revealed', clientSeed: 'mine', nonce: 3, rows: 12, risk: 'low' }
    for (const engineVersion of ENGINE_VERSIONS) {
      const verified = await verifyDrop({ ...seeds, engineVersion })
      expect(verified.engineVersion).toBe(engineVersion)
      expect(verified.stateHash).toBe(simulateDrop(createBoard({ rows: 12, risk: 'low', engineVersion }), verified.dropSeed).stateHash)
    }
    expect((await verifyDrop(seeds)).engineVersion).toBe(ENGINE_VERSION)
    await expect(verifyDrop({ ...seeds, engineVersion: '0.0.1' })).rejects.toThrow(UnknownEngineVersionError)
  })

  it('refuses to simulate a board whose version needs another solver', () => {
    const board = createBoard({ rows: 8, risk: 'low' })
    const foreign = { ...board, solver: { ...board.solver, restitutionThreshold: 10 } }
    expect(() => new DropSimulator(foreign)).toThrow(/needs solver restitutionThreshold = 10/)
  })

  it('has the calibration of every table of every version', () => {
    for (const version of ENGINE_VERSIONS) {
      for (let rows = 8; rows <= 16; rows++) {
        const calibration = calibrationOf(rows, version)
        expect(calibration.bucketCounts.reduce((a, b) => a + b, 0)).toBe(calibration.drops)
        for (const risk of ['low', 'medium', 'high']) expect(calibration.rtp[risk]).toBeCloseTo(0.99, 3)
      }
    }
  })
})
