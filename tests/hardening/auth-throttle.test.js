import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { spawnSync } from 'node:child_process'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { storeBackend } from '../server/helpers/stores.js'
import { startServer, eventually, OPERATOR_TOKEN } from '../server/helpers/server.js'
import { GameClient } from '../server/helpers/game-client.js'
import { loadConfig, ConfigError } from '../../server/config.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')
const LIMIT = 10
const BLOCK_MS = 1500

/** The value of one counter sample in /metrics text. */
function sample (text, name, kind) {
  const match = new RegExp(`^${name}\\{kind="${kind}"\\} (\\d+)$`, 'm').exec(text)
  return match ? Number(match[1]) : 0
}

/** A server with AUTH_FAILURE_LIMIT=LIMIT and AUTH_BLOCK_MS=BLOCK_MS for the describe() it is called in. */
function throttledServer () {
  const backend = storeBackend('sqlite')
  const started = { server: null }
  beforeAll(async () => {
    await backend.setup()
    started.server = await startServer(await backend.newDatabase(), { env: { AUTH_FAILURE_LIMIT: String(LIMIT), AUTH_BLOCK_MS: String(BLOCK_MS) } })
  })
  afterAll(async () => {
    await started.server?.close()
    await backend.teardown()
  })
  return started
}

/**
 * Issue #21, item 1: 40,045 wrong operator tokens in 10 s from one client
 * all got 403, and 700 unknown session tokens all got 401. Failed
 * authentication is now throttled per address (AUTH_FAILURE_LIMIT per
 * minute, then 429 with Retry-After for AUTH_BLOCK_MS, doubling).
 */
describe('failed authentication is throttled per address', () => {
  const started = throttledServer()
  let server
  beforeAll(() => { server = started.server })

  const get = (url, token, ip = '10.1.0.1') => server.app.inject({ method: 'GET', url, remoteAddress: ip, headers: token ? { authorization: `Bearer ${token}` } : {} })

  it('answers a guessing run 403 up to the budget, then 429 with Retry-After even for the right token, then a longer block', async () => {
    const statuses = []
    for (let i = 0; i < 40; i++) statuses.push((await get('/api/audit/drops', `wrong-operator-token-${i}`)).statusCode)
    expect(statuses.filter((s) => s === 403)).toHaveLength(LIMIT)
    expect(statuses.slice(0, LIMIT).every((s) => s === 403)).toBe(true)
    expect(statuses.slice(LIMIT).every((s) => s === 429)).toBe(true)

    // The real operator behind the same address waits out the block too: its token is not even looked at.
    const operator = await get('/api/audit/drops', OPERATOR_TOKEN)
    expect(operator.statusCode).toBe(429)
    expect(operator.json()).toEqual({ code: 'E_RATE_LIMITED', message: expect.stringMatching(/too many wrong operator tokens from this address; retry in \d+ s/) })
    const firstWait = Number(operator.headers['retry-after'])
    expect(firstWait).toBeGreaterThanOrEqual(1)
    expect(firstWait).toBeLessThanOrEqual(Math.ceil(BLOCK_MS / 1000))

    // Another address, and the player routes of this one, are not affected.
    expect((await get('/api/audit/drops', OPERATOR_TOKEN, '10.1.0.2')).statusCode).toBe(200)
    const session = (await server.app.inject({ method: 'POST', url: '/api/session', remoteAddress: '10.1.0.1' })).json()
    expect((await get('/api/me', session.token)).statusCode).toBe(200)

    // Once the block is over the operator gets in again; the next block in a row is twice as long.
    await eventually(async () => (await get('/api/audit/drops', OPERATOR_TOKEN)).statusCode === 200, { intervalMs: 100 })
    for (let i = 0; i < LIMIT; i++) expect((await get('/api/audit/drops', 'wrong-again')).statusCode).toBe(403)
    const second = await get('/api/audit/drops', OPERATOR_TOKEN)
    expect(second.statusCode).toBe(429)
    expect(Number(second.headers['retry-after'])).toBeGreaterThan(Math.ceil(BLOCK_MS / 1000))
  })

  it('throttles unknown session tokens over HTTP and over the WebSocket', async () => {
    const ip = '10.2.0.1'
    const statuses = []
    for (let i = 0; i < 25; i++) statuses.push((await get('/api/me', (i % 16).toString(16).repeat(64), ip)).statusCode)
    expect(statuses.filter((s) => s === 401)).toHaveLength(LIMIT)
    expect(statuses.filter((s) => s === 429)).toHaveLength(25 - LIMIT)
    // A missing token is no guess: still 401.
    expect((await server.app.inject({ method: 'GET', url: '/api/me', remoteAddress: '10.2.0.9' })).statusCode).toBe(401)

    // Over the WebSocket (all from 127.0.0.1): 4401 up to the budget, then E_RATE_LIMITED and close 1008.
    const codes = []
    for (let i = 0; i < LIMIT + 2; i++) {
      const client = new GameClient(server.wsUrl('f'.repeat(64)))
      const error = await client.take('error')
      codes.push(`${error.code} ${(await client.closed).code}`)
    }
    expect(codes.slice(0, LIMIT)).toEqual(Array(LIMIT).fill('E_UNAUTHORIZED 4401'))
    expect(codes.slice(LIMIT)).toEqual(['E_RATE_LIMITED 1008', 'E_RATE_LIMITED 1008'])
  })

  it('counts wrong tokens and throttled requests in /metrics', async () => {
    const text = (await server.app.inject({ method: 'GET', url: '/metrics', remoteAddress: '10.9.0.1' })).body
    expect(sample(text, 'plinko_auth_failures_total', 'operator')).toBe(2 * LIMIT)
    expect(sample(text, 'plinko_auth_failures_total', 'player')).toBe(2 * LIMIT)
    // 30 of the run, the right token once, the polls while the first block lasted, then one.
    expect(sample(text, 'plinko_auth_throttled_total', 'operator')).toBeGreaterThanOrEqual(40 - LIMIT + 2)
    expect(sample(text, 'plinko_auth_throttled_total', 'player')).toBe(25 - LIMIT + 2)
  })
})

/**
 * Issue #24, item 18: the operator page signs in through POST
 * /api/audit/token-check, which answers 200 whatever the token (so the
 * browser logs no refused request), yet counts a wrong one as the operator
 * routes do: the throttle cannot be dodged through it.
 */
describe('the operator token check', () => {
  const started = throttledServer()
  let server
  beforeAll(() => { server = started.server })

  const check = (token, ip) => server.app.inject({ method: 'POST', url: '/api/audit/token-check', remoteAddress: ip, headers: token ? { authorization: `Bearer ${token}` } : {} })
  const drops = (token, ip) => server.app.inject({ method: 'GET', url: '/api/audit/drops?limit=1', remoteAddress: ip, headers: { authorization: `Bearer ${token}` } })

  it('answers 200 with whether the token is the operator token', async () => {
    const ip = '10.5.0.1'
    const right = await check(OPERATOR_TOKEN, ip)
    expect([right.statusCode, right.json()]).toEqual([200, { valid: true }])
    const none = await check(null, ip)
    expect([none.statusCode, none.json()]).toEqual([200, { valid: false, code: 'E_UNAUTHORIZED', message: expect.any(String) }])
    const wrong = await check('not-the-operator-token', ip)
    expect([wrong.statusCode, wrong.json()]).toEqual([200, { valid: false, code: 'E_FORBIDDEN', message: 'wrong operator token' }])
    // Options are refused, as on POST /api/session; none, or {}, is the request.
    const body = await server.app.inject({ method: 'POST', url: '/api/audit/token-check', remoteAddress: ip, headers: { authorization: `Bearer ${OPERATOR_TOKEN}` }, payload: { token: OPERATOR_TOKEN } })
    expect([body.statusCode, body.json().code]).toEqual([400, 'E_BAD_REQUEST'])
    const empty = await server.app.inject({ method: 'POST', url: '/api/audit/token-check', remoteAddress: ip, headers: { authorization: `Bearer ${OPERATOR_TOKEN}` }, payload: {} })
    expect(empty.json()).toEqual({ valid: true })
  })

  it('counts each wrong token: after AUTH_FAILURE_LIMIT of them the audit routes answer the address 429, and the check says how long to wait', async () => {
    const ip = '10.5.0.2'
    for (let i = 0; i < LIMIT; i++) {
      const wrong = await check(`wrong-operator-token-${i}`, ip)
      expect([wrong.statusCode, wrong.json().code], `guess ${i}`).toEqual([200, 'E_FORBIDDEN'])
    }
    // The real routes, with the right token, from that address: blocked.
    const blocked = await drops(OPERATOR_TOKEN, ip)
    expect(blocked.statusCode).toBe(429)
    expect(blocked.json().code).toBe('E_RATE_LIMITED')
    expect(Number(blocked.headers['retry-after'])).toBeGreaterThanOrEqual(1)
    // The check tells the blocked address so, whatever the token: a right guess looks like a wrong one.
    for (const token of [OPERATOR_TOKEN, 'another-guess']) {
      const answer = await check(token, ip)
      expect(answer.statusCode).toBe(200)
      expect(answer.json()).toEqual({ valid: false, code: 'E_RATE_LIMITED', message: expect.stringMatching(/retry in \d+ s/), retryAfter: expect.any(Number) })
      expect(answer.json().retryAfter).toBeLessThanOrEqual(Math.ceil(BLOCK_MS / 1000))
      expect(answer.headers['retry-after']).toBeUndefined()
    }
    // Another address is not affected.
    expect((await check(OPERATOR_TOKEN, '10.5.0.3')).json()).toEqual({ valid: true })
    expect((await drops(OPERATOR_TOKEN, '10.5.0.3')).statusCode).toBe(200)
    // Guesses on the check and on the routes add up to one budget.
    await eventually(async () => (await check(OPERATOR_TOKEN, ip)).json().valid === true, { intervalMs: 100 })
    for (let i = 0; i < LIMIT - 1; i++) expect((await check('wrong-again', ip)).json().code).toBe('E_FORBIDDEN')
    expect((await drops('wrong-again', ip)).statusCode).toBe(403)
    expect((await drops(OPERATOR_TOKEN, ip)).statusCode).toBe(429)
  })
})

describe('an OPERATOR_TOKEN too weak to survive guessing', () => {
  const weak = ['passwordpasswordpassword', 'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa', 'hunter2hunter2hunter2hunter2', 'short-secret']
  it('is refused with a ConfigError that says why, and never shows the token', () => {
    for (const token of weak) {
      let error
      try { loadConfig({ OPERATOR_TOKEN: token }) } catch (caught) { error = caught }
      expect(error, token).toBeInstanceOf(ConfigError)
      expect(error.code).toBe('E_CONFIG')
      expect(error.message, token).toMatch(/OPERATOR_TOKEN=\(value hidden\): (too weak to survive guessing|must be at least 24 characters)/)
      expect(error.message).not.toContain(token)
    }
    for (const token of [OPERATOR_TOKEN, 'e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855', 'k3Tq9vXz0pLm7RwA2sYb8NcF']) {
      expect(loadConfig({ OPERATOR_TOKEN: token }).operatorToken).toBe(token)
    }
  })

  it('keeps the server from starting, with that reason on one line', () => {
    const child = spawnSync(process.execPath, ['server/server.js'], {
      cwd: ROOT,
      env: { ...process.env, OPERATOR_TOKEN: 'passwordpasswordpassword', DATABASE_URL: 'sqlite::memory:', PORT: '0', HOST: '127.0.0.1' },
      encoding: 'utf8',
      timeout: 20_000
    })
    expect(child.status).toBe(1)
    expect(child.stderr).toContain('OPERATOR_TOKEN=(value hidden): too weak to survive guessing')
  })
})
