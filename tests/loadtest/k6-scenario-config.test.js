import { describe, it, expect, beforeEach } from 'vitest'

// The k6 scenario settings module only reads the global __ENV (k6's); give it one.
globalThis.__ENV = {}
const { loopbackBaseUrl, ownerSocketUrl, parseSeconds, readScenarioConfig, playerScenarioOptions } = await import('../../loadtest/k6-lib/scenario-config.js')

describe('k6 scenario settings', () => {
  beforeEach(() => { globalThis.__ENV = {} })

  it('refuses any BASE_URL that is not on loopback', () => {
    expect(loopbackBaseUrl('http://127.0.0.1:8080/')).toBe('http://127.0.0.1:8080')
    expect(loopbackBaseUrl('http://localhost:1234')).toBe('http://localhost:1234')
    for (const url of ['http://example.com', 'http://192.168.1.2:8080', 'http://127.0.0.1.evil.com', 'http://localhost.evil.com:80', 'http://localhost:8080/path']) {
      expect(() => loopbackBaseUrl(url), url).toThrow(/not on this machine/)
    }
  })

  it('follows an E_WRONG_NODE owner only on loopback, to its /ws', () => {
    expect(ownerSocketUrl('http://127.0.0.1:8080/n/1')).toBe('ws://127.0.0.1:8080/n/1/ws')
    expect(ownerSocketUrl('http://localhost:9000')).toBe('ws://localhost:9000/ws')
    expect(ownerSocketUrl('https://[::1]:8443/n/server2/')).toBe('wss://[::1]:8443/n/server2/ws')
    for (const owner of ['http://10.0.0.5:8080/n/1', 'http://127.0.0.1.evil.com/n/1', 'http://localhost:8080/n/1?x=1', 'ws://127.0.0.1/', null, 42]) {
      expect(ownerSocketUrl(owner), String(owner)).toBeNull()
    }
  })

  it('reads its settings from __ENV, with the scenario defaults', () => {
    globalThis.__ENV = { BASE_URL: 'http://127.0.0.1:9999', VUS: '300', ROOMS: '7', DROP_INTERVAL: '1500ms' }
    const config = readScenarioConfig({ duration: '20s', ramp: '5s' })
    expect(config).toMatchObject({ baseUrl: 'http://127.0.0.1:9999', wsUrl: 'ws://127.0.0.1:9999/ws', vus: 300, rooms: 7, dropIntervalMs: 1500, durationS: 20, rampS: 5 })
    expect(parseSeconds('2m', 0)).toBe(120)
  })

  it('bounds every scenario and fails on errors and unsettled drops', () => {
    globalThis.__ENV = { DURATION: '30s', RAMP: '10s', DRAIN: '20s' }
    const options = playerScenarioOptions(readScenarioConfig(), 'players')
    expect(options.scenarios.players).toMatchObject({ executor: 'per-vu-iterations', iterations: 1, maxDuration: '120s' })
    expect(options.thresholds).toMatchObject({ plinko_errors: ['count==0'], unsettled_drops: ['count==0'], balance_mismatches: ['count==0'] })
  })

  it('plays snapshots by default and seeds on DELIVERY=seeds, where the jitter threshold gives way to drop events received', () => {
    expect(readScenarioConfig().delivery).toBe('snapshots')
    expect(playerScenarioOptions(readScenarioConfig(), 'p').thresholds.snapshot_jitter_ms).toBeDefined()
    globalThis.__ENV = { DELIVERY: 'seeds' }
    const options = playerScenarioOptions(readScenarioConfig(), 'p')
    expect(options.thresholds.snapshot_jitter_ms).toBeUndefined()
    expect(options.thresholds.drop_events_received).toEqual(['count>0'])
    globalThis.__ENV = { DELIVERY: 'pixels' }
    expect(() => readScenarioConfig()).toThrow(/DELIVERY must be one of snapshots, seeds/)
  })
})
