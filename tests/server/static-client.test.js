import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { buildApp } from '../../server/app.js'
import { loadConfig } from '../../server/config.js'

describe('static client', () => {
  let dir
  beforeAll(() => { dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-client-')) })
  afterAll(() => fs.rmSync(dir, { recursive: true, force: true }))

  async function appWithClientDir (clientDir) {
    const config = loadConfig({ DATABASE_URL: 'sqlite::memory:', OPERATOR_TOKEN: 'operator-token-for-tests-0123456789', CLIENT_DIR: clientDir, LOG_LEVEL: 'silent' })
    return buildApp(config, { logger: false })
  }

  it('serves index.html at / and audit.html at /audit when the client is built', async () => {
    const clientDir = path.join(dir, 'built')
    fs.mkdirSync(clientDir)
    fs.writeFileSync(path.join(clientDir, 'index.html'), '<!doctype html><title>Plinko</title>')
    fs.writeFileSync(path.join(clientDir, 'audit.html'), '<!doctype html><title>Audit</title>')
    fs.writeFileSync(path.join(clientDir, 'app.js'), 'console.log(1)')
    const app = await appWithClientDir(clientDir)
    try {
      const index = await app.inject({ method: 'GET', url: '/' })
      expect(index.statusCode).toBe(200)
      expect(index.body).toContain('<title>Plinko</title>')
      expect(index.headers['content-security-policy']).toContain("default-src 'self'")
      expect((await app.inject({ method: 'GET', url: '/audit' })).body).toContain('<title>Audit</title>')
      expect((await app.inject({ method: 'GET', url: '/app.js' })).statusCode).toBe(200)
      // The API still wins over the static wildcard, and unknown paths are E_NOT_FOUND.
      expect((await app.inject({ method: 'GET', url: '/api/rooms' })).json().roomIds).toHaveLength(216)
      const missing = await app.inject({ method: 'GET', url: '/nope.html' })
      expect(missing.statusCode).toBe(404)
      expect(missing.json().code).toBe('E_NOT_FOUND')
    } finally {
      await app.close()
    }
  })

  it('starts without a client folder, or with an empty one', async () => {
    const empty = path.join(dir, 'empty')
    fs.mkdirSync(empty)
    for (const clientDir of [path.join(dir, 'missing'), empty]) {
      const app = await appWithClientDir(clientDir)
      try {
        const root = await app.inject({ method: 'GET', url: '/' })
        expect(root.statusCode).toBe(404)
        expect(root.json().code).toBe('E_NOT_FOUND')
        expect((await app.inject({ method: 'GET', url: '/api/health' })).json()).toMatchObject({ status: 'ok', store: 'sqlite' })
      } finally {
        await app.close()
      }
    }
  })
})
