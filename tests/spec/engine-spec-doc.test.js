/**
 * docs/engine-spec.md says what the engine does: its tables (constants of
 * every version, solver constants, multiplier tables) and its inline test
 * vectors are read back here and compared with engine/ and with
 * docs/engine-spec-vectors.json, so the text cannot drift from the code.
 */
import { describe, it, expect } from 'vitest'
import { readFileSync } from 'node:fs'
import { fileURLToPath } from 'node:url'
import { engineRules, ENGINE_VERSIONS, RISKS, SOLVER, MIN_ROWS, MAX_ROWS } from '../../engine/index.js'

const SPEC = readFileSync(fileURLToPath(new URL('../../docs/engine-spec.md', import.meta.url)), 'utf8')
const VECTORS = JSON.parse(readFileSync(fileURLToPath(new URL('../../docs/engine-spec-vectors.json', import.meta.url)), 'utf8'))

/** The body of section `heading` (a line starting with it) up to the next heading of any level. */
function section (heading) {
  const start = SPEC.indexOf('\n' + heading)
  expect(start, heading).toBeGreaterThan(-1)
  const body = SPEC.slice(start + heading.length + 1)
  const end = body.search(/\n#{2,4} /)
  return end < 0 ? body : body.slice(0, end)
}

/** Rows of the markdown tables in `text`, as arrays of cell texts (header and rule lines left out). */
function tableRows (text) {
  return text.split('\n').filter((line) => line.startsWith('|') && !/^\|[\s|:-]+\|$/.test(line))
    .map((line) => line.slice(1, -1).split('|').map((cell) => cell.trim()))
    .slice(1)
}

const code = (cell) => cell.replace(/^`|`$/g, '')

describe('docs/engine-spec.md', () => {
  it('gives every solver constant the engine runs, with its value', () => {
    const rows = Object.fromEntries(tableRows(section('### 1.1')).map(([name, value]) => [code(name), value]))
    for (const [name, value] of Object.entries(SOLVER)) {
      const key = name === 'timestep' ? 'dt' : name
      expect(rows[key], name).toBeDefined()
      expect(name === 'timestep' ? 1 / 60 : Number(rows[key]), name).toBe(value)
    }
  })

  it('gives every version\'s geometry, materials, release bounds and tick cap', () => {
    const rows = tableRows(section('### 1.2'))
    const column = (version) => 1 + ENGINE_VERSIONS.indexOf(version)
    const numbers = (cell) => cell.split(',').map(Number)
    for (const version of ENGINE_VERSIONS) {
      const rules = engineRules(version)
      const value = (label) => rows.find(([name]) => name === label || code(name) === label)[column(version)]
      for (const [key, number] of Object.entries(rules.geometry)) expect(Number(value(key)), `${version} ${key}`).toBe(number)
      const material = ({ density, restitution, friction }) => [density, restitution, friction]
      expect(numbers(value('ball: density, restitution, friction'))).toEqual(material(rules.ballMaterial))
      expect(numbers(value('pegs and walls: density, restitution, friction'))).toEqual(material(rules.pegMaterial))
      expect(numbers(value('release: `maxVx`, `maxVy`, `maxSpin`'))).toEqual([rules.release.maxVx, rules.release.maxVy, rules.release.maxSpin])
      expect(Number(value('maxDropTicks'))).toBe(rules.maxDropTicks)
    }
  })

  it('lists all 27 multiplier tables of every version, exactly', () => {
    ENGINE_VERSIONS.forEach((version, i) => {
      const rows = tableRows(section(`### 9.${i + 1} Engine ${version}`))
      const expected = []
      for (let n = MIN_ROWS; n <= MAX_ROWS; n++) {
        for (const risk of RISKS) expected.push([String(n), risk, engineRules(version).multipliers[n][risk].map(String).join(' ')])
      }
      expect(rows).toEqual(expected)
    })
  })

  it('shows test vectors that are the vectors file\'s', () => {
    const seeds = tableRows(section('### 12.1'))
    expect(seeds.map(([server, client, nonce, hash, drop]) => [code(server), client === '(empty)' ? '' : code(client), Number(nonce), code(hash), code(drop)]))
      .toEqual(VECTORS.seeds.map((s) => [s.serverSeed, s.clientSeed, s.nonce, s.serverSeedHash, s.dropSeed]))
    const random = section('### 12.2').split('\n').filter((line) => line.startsWith('- seed'))
    expect(random.map((line) => line.match(/`(.*)`: (.*)$/).slice(1)).map(([seed, list]) => ({ seed, doubles: list.split(', ').map(Number) })))
      .toEqual(VECTORS.random)
    expect(tableRows(section('### 12.3')).map(([, hash]) => code(hash))).toEqual(VECTORS.stateHash.map((s) => s.hash))
    for (const version of ENGINE_VERSIONS) {
      const rows = tableRows(section(`#### Engine ${version}`))
      expect(rows.length).toBe(9)
      for (const [n, risk, nonce, release, tick1, tick10, tick100, bucket, ticks, stateHash] of rows) {
        const drop = VECTORS.versions[version].drops.find((d) => d.nonce === Number(nonce))
        expect([drop.rows, drop.risk]).toEqual([Number(n), risk])
        const { x, vx, vy, angle, angularVelocity } = drop.initial
        expect(release.split(', ').map(Number)).toEqual([x, vx, vy, angle, angularVelocity])
        expect([code(tick1), code(tick10), tick100 === '(landed)' ? undefined : code(tick100)])
          .toEqual([drop.stateHashAfterTick[1], drop.stateHashAfterTick[10], drop.stateHashAfterTick[100]])
        expect([Number(bucket), Number(ticks), code(stateHash)]).toEqual([drop.bucket, drop.ticks, drop.stateHash])
      }
    }
  })
})
