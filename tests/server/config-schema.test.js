/**
 * server/config.js states the environment as a JSON schema (env-schema on
 * ajv): these check what the schema form has to keep from the hand-written
 * checks it replaced (the text of every refusal, integers written only in
 * decimal, empty = unset, one problem per variable), and that the README's
 * configuration table lists every variable with the schema's default.
 */
import { describe, it, expect } from 'vitest'
import { readFileSync } from 'node:fs'
import { loadConfig, ConfigError, CONFIG_SCHEMA, CONFIG_VARIABLES } from '../../server/config.js'

function problems (env) {
  try {
    loadConfig(env)
  } catch (error) {
    expect(error).toBeInstanceOf(ConfigError)
    expect(error.code).toBe('E_CONFIG')
    expect(error.message).toBe('invalid configuration:\n  ' + error.problems.join('\n  '))
    return error.problems
  }
  return []
}

describe('configuration schema', () => {
  it('reads integers only as decimal text within the range, as before', () => {
    expect(loadConfig({ PORT: ' 8081 ', MAX_BALLS_PER_ROOM: '4096', LEASE_TTL_MS: '300' })).toMatchObject({ port: 8081, maxBallsPerRoom: 4096, leaseTtlMs: 300 })
    for (const text of ['1e3', '0x10', '1.0', '1.5', '80a', '-1', '65536', '99999999999999999999', ' ']) {
      expect(problems({ PORT: text }), text).toEqual([`PORT=${JSON.stringify(text)}: must be an integer from 0 to 65535`])
    }
    expect(problems({ STARTING_BALANCE: '9007199254740992' })).toEqual(['STARTING_BALANCE="9007199254740992": must be an integer from 0 to 9007199254740991'])
    expect(loadConfig({ STARTING_BALANCE: '9007199254740991' }).startingBalance).toBe(Number.MAX_SAFE_INTEGER)
  })

  it('takes an empty variable as unset, and gives every default', () => {
    const defaults = loadConfig({})
    const empty = loadConfig(Object.fromEntries(CONFIG_VARIABLES.map((name) => [name, ''])))
    expect({ ...empty, operatorToken: 'x' }).toEqual({ ...defaults, operatorToken: 'x' })
    expect(empty.operatorTokenGenerated).toBe(true)
    expect(defaults).toMatchObject({ snapshotHz: 20, spectatorEvents: 'snapshot', leaseTtlMs: 5000, wsHardBuffer: 1048576, trustProxy: false, redisUrl: '', publicUrl: '' })
  })

  it('gives the most specific reason, once per variable, in the schema\'s order', () => {
    expect(problems({ DATABASE_URL: 'sqlite:' })).toEqual(['DATABASE_URL=(value hidden): sqlite: needs a file path, e.g. sqlite:./data/plinko.sqlite'])
    expect(problems({ DATABASE_URL: 'postgres://[x' })).toEqual(['DATABASE_URL=(value hidden): is not a valid postgres:// URL'])
    expect(problems({ REDIS_URL: 'redis://[secret', DATABASE_URL: 'postgres://db/x' })).toEqual(['REDIS_URL=(value hidden): is not a valid redis:// URL'])
    expect(problems({ REDIS_URL: 'http://secret' })).toEqual(['REDIS_URL=(value hidden): must be redis://[user:password@]host:port[/db] or rediss://…'])
    expect(problems({ TRUST_PROXY: '11' })).toEqual(['TRUST_PROXY="11": as a number of proxy hops must be from 1 to 10'])
    expect(problems({ TRUST_PROXY: '10.0.0.0/8, example.com' })).toEqual(['TRUST_PROXY="10.0.0.0/8, example.com": must be false, a number of proxy hops, or proxy addresses (IPs, subnets, loopback, linklocal, uniquelocal); "example.com" is none of them'])
    expect(problems({ PUBLIC_URL: 'ftp://x', HOST: '  ', LOG_LEVEL: 'loud', PORT: 'x' })).toEqual([
      'PORT="x": must be an integer from 0 to 65535',
      'HOST="  ": must not be empty',
      'LOG_LEVEL="loud": must be one of fatal, error, warn, info, debug, trace, silent',
      'PUBLIC_URL="ftp://x": must be an absolute http:// or https:// URL'
    ])
    expect(loadConfig({ PUBLIC_URL: 'http://lb:8080/n/a//', TRUST_PROXY: ' 2 ' })).toMatchObject({ publicUrl: 'http://lb:8080/n/a', trustProxy: 2 })
  })

  it('checks the rules between variables only once each one is valid', () => {
    expect(problems({ WS_SOFT_BUFFER: '1048576' })).toEqual(['WS_HARD_BUFFER must be > WS_SOFT_BUFFER'])
    expect(problems({ REDIS_URL: 'redis://r:6379' })).toEqual(['REDIS_URL (clustering) needs DATABASE_URL=postgres://…: the processes share one ledger'])
    expect(problems({ MIN_BET: '10', MAX_BET: '5', PORT: 'x' })).toEqual(['PORT="x": must be an integer from 0 to 65535'])
  })

  it('marks the secrets, and never echoes them', () => {
    const secrets = CONFIG_VARIABLES.filter((name) => CONFIG_SCHEMA.properties[name].writeOnly)
    expect(secrets).toEqual(['DATABASE_URL', 'OPERATOR_TOKEN', 'REDIS_URL'])
    const message = problems({ DATABASE_URL: 'mysql://hunter2@db', OPERATOR_TOKEN: 'hunter2', REDIS_URL: 'hunter2://x' }).join('\n')
    expect(message).not.toContain('hunter2')
    expect(message.match(/\(value hidden\)/g)).toHaveLength(3)
  })

  it('is listed, variable by variable with its default, in the configuration table of docs/server.md', () => {
    const readme = readFileSync(new URL('../../docs/server.md', import.meta.url), 'utf8')
    const section = readme.slice(readme.indexOf('## Configuration'))
    const rows = section.slice(0, section.indexOf('\n\n', section.indexOf('| --- |'))).split('\n').filter((line) => line.startsWith('| `'))
    const documented = new Map()
    for (const row of rows) {
      const [names, defaults] = row.split(' | ').map((cell) => cell.replace(/^\| /, ''))
      const variables = [...names.matchAll(/`([A-Z_0-9]+)`/g)].map((m) => m[1])
      const values = defaults.split(', ')
      variables.forEach((name, i) => documented.set(name, variables.length === values.length ? values[i] : defaults))
    }
    expect([...documented.keys()].sort()).toEqual([...CONFIG_VARIABLES].sort())
    for (const name of CONFIG_VARIABLES) {
      const fallback = CONFIG_SCHEMA.properties[name].default
      // Defaults that are values (not a generated token, a path in the checkout or "unset") are written as they are.
      if (fallback !== '' && name !== 'CLIENT_DIR') expect(documented.get(name), name).toBe(fallback)
    }
  })
})
