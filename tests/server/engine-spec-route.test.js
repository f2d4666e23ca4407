import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import fs from 'node:fs'
import { buildApp } from '../../server/app.js'
import { loadConfig } from '../../server/config.js'

/** The specification and its vectors, served as they are in the repository, and linked from the operator page. */
describe('GET /docs/engine-spec.md and /docs/engine-spec-vectors.json', () => {
  let app
  beforeAll(async () => {
    const config = loadConfig({ DATABASE_URL: 'sqlite::memory:', OPERATOR_TOKEN: 'operator-token-for-tests-0123456789', LOG_LEVEL: 'silent' })
    app = await buildApp(config, { logger: false })
  })
  afterAll(async () => { await app?.close() })

  it('serve the repository\'s files byte for byte, with their types', async () => {
    for (const [url, type] of [['/docs/engine-spec.md', 'text/markdown'], ['/docs/engine-spec-vectors.json', 'application/json']]) {
      const reply = await app.inject({ method: 'GET', url })
      expect(reply.statusCode, url).toBe(200)
      expect(reply.headers['content-type']).toContain(type)
      expect(reply.rawPayload.equals(fs.readFileSync(new URL(`../..${url}`, import.meta.url))), url).toBe(true)
    }
    // Swagger UI keeps its own page under /docs.
    expect((await app.inject({ method: 'GET', url: '/docs' })).statusCode).toBe(200)
  })

  it('are what the operator page links to', () => {
    const page = fs.readFileSync(new URL('../../client/audit.html', import.meta.url), 'utf8')
    expect(page).toContain('href="/docs/engine-spec.md"')
    expect(page).toContain('href="/docs/engine-spec-vectors.json"')
  })
})
