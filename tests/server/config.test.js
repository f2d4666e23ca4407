import { describe, it, expect } from 'vitest'
import { spawnSync } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { loadConfig, ConfigError, CONFIG_VARIABLES } from '../../server/config.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')

describe('configuration', () => {
  it('has the documented defaults', () => {
    const config = loadConfig({})
    expect(config).toMatchObject({
      port: 8080,
      host: '0.0.0.0',
      database: { kind: 'sqlite', file: path.join(ROOT, 'data', 'plinko.sqlite') },
      operatorTokenGenerated: true,
      snapshotHz: 20,
      startingBalance: 100000,
      minBet: 1,
      maxBet: 1000000,
      logLevel: 'info',
      dropRate: 20,
      wsMaxPayload: 4096,
      ledgerCommitTicks: 2
    })
    expect(config.operatorToken).toMatch(/^[0-9a-f]{64}$/)
    expect(loadConfig({}).operatorToken).not.toBe(config.operatorToken)
    expect(CONFIG_VARIABLES).toContain('SNAPSHOT_HZ')
  })

  it('trusts X-Forwarded-For only as far as TRUST_PROXY names the proxies, never the client\'s own left-most hop', () => {
    expect(loadConfig({}).trustProxy).toBe(false)
    expect(loadConfig({ TRUST_PROXY: 'false' }).trustProxy).toBe(false)
    expect(loadConfig({ TRUST_PROXY: '1' }).trustProxy).toBe(1)
    expect(loadConfig({ TRUST_PROXY: 'loopback' }).trustProxy).toEqual(['loopback'])
    expect(loadConfig({ TRUST_PROXY: '10.0.0.0/8, 127.0.0.1,::1, fd00::/8' }).trustProxy).toEqual(['10.0.0.0/8', '127.0.0.1', '::1', 'fd00::/8'])
    for (const bad of ['true', '0', '11', 'yes', '10.0.0.0/33', '300.1.1.1', 'loopback,', 'example.com']) {
      expect(() => loadConfig({ TRUST_PROXY: bad }), bad).toThrow(/TRUST_PROXY/)
    }
    expect(() => loadConfig({ TRUST_PROXY: 'true' })).toThrow(/would believe the client's own X-Forwarded-For/)
  })

  it('parses database URLs', () => {
    expect(loadConfig({ DATABASE_URL: 'sqlite:/tmp/x.sqlite' }).database).toEqual({ kind: 'sqlite', file: '/tmp/x.sqlite', busyTimeoutMs: 5000 })
    expect(loadConfig({ DATABASE_URL: 'sqlite::memory:', SQLITE_BUSY_TIMEOUT_MS: '250' }).database).toEqual({ kind: 'sqlite', file: ':memory:', busyTimeoutMs: 250 })
    expect(loadConfig({ DATABASE_URL: 'postgres://u:p@db:5432/plinko' }).database).toEqual({ kind: 'postgres', url: 'postgres://u:p@db:5432/plinko' })
    expect(loadConfig({ DATABASE_URL: 'postgresql://db/plinko' }).database.kind).toBe('postgres')
  })

  it('reports every invalid variable at once and never echoes secrets', () => {
    let error
    try {
      loadConfig({ PORT: '80a', SNAPSHOT_HZ: '7', MIN_BET: '0', LOG_LEVEL: 'loud', OPERATOR_TOKEN: 'short-secret', DATABASE_URL: 'mysql://secret@x' })
    } catch (e) { error = e }
    expect(error).toBeInstanceOf(ConfigError)
    expect(error.problems).toHaveLength(6)
    expect(error.message).toMatch(/PORT="80a"/)
    expect(error.message).toMatch(/SNAPSHOT_HZ="7": must be one of 1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30, 60/)
    expect(error.message).not.toContain('short-secret')
    expect(error.message).not.toContain('mysql://secret')
    expect(() => loadConfig({ MIN_BET: '10', MAX_BET: '5' })).toThrow(/MAX_BET must be >= MIN_BET/)
    expect(loadConfig({ LEDGER_COMMIT_TICKS: '1' }).ledgerCommitTicks).toBe(1)
    expect(() => loadConfig({ LEDGER_COMMIT_TICKS: '16' })).toThrow(/LEDGER_COMMIT_TICKS="16": must be an integer from 1 to 15/)
  })

  it('makes `npm start` exit non-zero with a clear message on bad configuration', () => {
    const result = spawnSync(process.execPath, [path.join(ROOT, 'server/server.js')], {
      env: { ...process.env, PORT: 'eighty', STARTING_BALANCE: '-1' },
      encoding: 'utf8',
      timeout: 30_000
    })
    expect(result.status).toBe(1)
    expect(result.stderr).toContain('invalid configuration')
    expect(result.stderr).toContain('PORT="eighty"')
    expect(result.stderr).toContain('STARTING_BALANCE')
  })
})
