import { describe, it, expect } from 'vitest'
import { parseArgs, parseDuration, loopbackTarget, UsageError } from '../../loadtest/driver/cli-args.js'

describe('loadtest command line', () => {
  it('reads the documented options', () => {
    const options = parseArgs(['--vus', '2000', '--duration', '60s', '--rooms=100', '--drop-interval', '2s', '--scenario', 'spike',
      '--env', 'SNAPSHOT_HZ=10', '-e', 'SETTLE_P99_MS=250', '--pin', '--profile'])
    expect(options).toMatchObject({
      scenario: 'spike', vus: 2000, durationS: 60, rooms: 100, dropIntervalS: 2, pin: true, profile: true,
      serverEnv: { SNAPSHOT_HZ: '10' }, k6Env: { SETTLE_P99_MS: '250' }
    })
  })

  it('has defaults that leave scenario timings to the scenario', () => {
    const options = parseArgs([])
    expect(options).toMatchObject({ scenario: 'players', vus: 50, rooms: 10, dropIntervalS: 2, profile: false, pin: false, delivery: 'snapshots' })
    expect(parseArgs(['--delivery', 'seeds']).delivery).toBe('seeds')
    expect(options.durationS).toBeUndefined()
    expect(options.rampS).toBeUndefined()
  })

  it('refuses what it does not understand', () => {
    expect(() => parseArgs(['--vus', '0'])).toThrow(UsageError)
    expect(() => parseArgs(['--vus'])).toThrow(/needs a value/)
    expect(() => parseArgs(['--scenario', 'flood'])).toThrow(/players, spike, soak/)
    expect(() => parseArgs(['--duration', 'soon'])).toThrow(/not a duration/)
    expect(() => parseArgs(['--env', 'no-equals'])).toThrow(/KEY=VALUE/)
    expect(() => parseArgs(['--frobnicate'])).toThrow(/unknown option --frobnicate/)
    expect(() => parseArgs(['--delivery', 'frames'])).toThrow(/--delivery must be one of snapshots, seeds/)
    expect(() => parseArgs(['spike'])).toThrow(/unexpected argument "spike"/)
    expect(() => parseArgs(['--vus', '--pin'])).toThrow(/--vus needs a value/)
    expect(() => parseArgs(['--pin=yes'])).toThrow(/--pin takes no value/)
    expect(() => parseArgs(['--e', 'A=1'])).toThrow(/unknown option --e/)
    expect(() => parseArgs(['--drain', '-5s'])).toThrow(/not a duration: -5s for --drain/)
  })

  it('is node:util parseArgs underneath: inline values, repeatable -e and --env, the last of a repeated option wins', () => {
    const options = parseArgs(['--vus=10', '-eA=1', '-e', 'B=2', '--env', 'X=1', '--env=Y=2=3', '--vus', '20', '--duration=90s', '--duration', '2m'])
    expect(options).toMatchObject({ vus: 20, durationS: 120, k6Env: { A: '1', B: '2' }, serverEnv: { X: '1', Y: '2=3' } })
    for (const error of [() => parseArgs(['--vus', '0']), () => parseArgs(['--frobnicate'])]) {
      expect(error).toThrow(UsageError)
    }
  })

  it('answers --help whatever else the line holds', () => {
    expect(parseArgs(['--help']).help).toBe(true)
    expect(parseArgs(['--vus', '0', '-h', '--frobnicate'])).toMatchObject({ help: true, scenario: 'players', vus: 50 })
    expect(parseArgs([]).help).toBe(false)
  })

  it('parses durations', () => {
    expect(parseDuration('90')).toBe(90)
    expect(parseDuration('1500ms')).toBe(1.5)
    expect(parseDuration('10m')).toBe(600)
    expect(parseDuration('1h')).toBe(3600)
  })

  it('targets loopback only', () => {
    expect(loopbackTarget('http://127.0.0.1:8080')).toBe('http://127.0.0.1:8080')
    expect(loopbackTarget('http://localhost:3000/')).toBe('http://localhost:3000')
    expect(loopbackTarget('http://[::1]:8080')).toBe('http://[::1]:8080')
    for (const url of ['http://example.com', 'http://10.0.0.5:8080', 'http://127.0.0.1.nip.io', 'ftp://127.0.0.1', 'http://user:pw@localhost', 'http://localhost/api', 'not a url']) {
      expect(() => loopbackTarget(url), url).toThrow(UsageError)
    }
  })
})
