/**
 * How the browser gets the engine and the wire format (no browser needed):
 * the pages, the repository's engine/ files at /engine/, protocol/ files at
 * /protocol/ and charts/ files at /charts/, byte for byte the server's own,
 * seedrandom as an ES module at /vendor/seedrandom.js, and a Content-Security-Policy that admits the
 * pages' inline import maps by hash and no other inline script.
 */
import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { createHash } from 'node:crypto'
import { readFileSync, readdirSync } from 'node:fs'
import { fileURLToPath } from 'node:url'
import seedrandom from 'seedrandom'
import { startArenaServer, CLIENT_DIR } from '../e2e/helpers/arena-server.js'

const ENGINE_DIR = fileURLToPath(new URL('../../engine/', import.meta.url))
const PROTOCOL_DIR = fileURLToPath(new URL('../../protocol/', import.meta.url))
const CHARTS_DIR = fileURLToPath(new URL('../../charts/', import.meta.url))

let server

beforeAll(async () => {
  server = await startArenaServer()
})

afterAll(async () => {
  await server?.close()
})

describe('client assets', () => {
  it('serves the player page at /, the operator page at /audit and the share page, their links to versioned files with the version', async () => {
    for (const [url, file] of [['/', 'index.html'], ['/audit', 'audit.html'], ['/share/1/0123456789abcdef0123', 'share.html']]) {
      const response = await server.api('GET', url)
      expect(response.status).toBe(200)
      expect(response.headers['content-type']).toMatch(/^text\/html/)
      expect(response.headers['cache-control']).toBe('no-cache')
      // The file as it is, but for ?v=<version> after the stylesheet, the icon and the bundle.
      expect(response.text.replace(/\?v=[\w-]{12}"/g, '"')).toBe(readFileSync(`${CLIENT_DIR}/${file}`, 'utf8'))
      expect(response.text).toMatch(/href="\/style\.css\?v=[\w-]{12}"/)
    }
  })

  it('lets browsers keep versioned files for a year without asking again, and compresses each file once', async () => {
    const page = (await server.api('GET', '/')).text
    const links = [...page.matchAll(/"(\/(?:bundle\/player\.js|bundle\/board-worker\.js|style\.css|favicon\.svg))\?v=([\w-]{12})"/g)].map((m) => ({ url: m[1], version: m[2] }))
    expect(links.map((l) => l.url).sort()).toEqual(['/bundle/board-worker.js', '/bundle/player.js', '/favicon.svg', '/style.css'])
    for (const { url, version } of links) {
      const current = await server.api('GET', `${url}?v=${version}`)
      expect(current.status, url).toBe(200)
      expect(current.headers['cache-control'], url).toBe('public, max-age=31536000, immutable')
      // Another version (an old page's link), or none: revalidated, never kept.
      for (const other of [`${url}?v=000000000000`, url]) expect((await server.api('GET', other)).headers['cache-control'], other).toBe('no-cache')
      // The version is the content's: the file's own bytes.
      if (!url.startsWith('/bundle/')) expect(current.text, url).toBe(readFileSync(`${CLIENT_DIR}/${url.slice(1)}`, 'utf8'))
    }
    // Compressed once: the same Brotli bytes each time, sent whole with their length (not streamed through a compressor per request).
    const http = await import('node:http')
    const raw = (url) => new Promise((resolve, reject) => {
      http.get(`${server.base}${url}`, { headers: { 'accept-encoding': 'br' } }, (response) => {
        const chunks = []
        response.on('data', (chunk) => chunks.push(chunk))
        response.on('end', () => resolve({ headers: response.headers, body: Buffer.concat(chunks) }))
      }).on('error', reject)
    })
    for (const url of ['/bundle/player.js', '/bundle/board-worker.js', '/engine/world.js', '/']) {
      const [first, second] = [await raw(url), await raw(url)]
      expect(first.headers['content-encoding'], url).toBe('br')
      expect(Number(first.headers['content-length']), url).toBe(first.body.length)
      expect(first.headers.vary, url).toMatch(/accept-encoding/i)
      expect(second.body.equals(first.body), url).toBe(true)
    }
  })

  it('serves every engine file unchanged at /engine/, and nothing else from there', async () => {
    const names = readdirSync(ENGINE_DIR, { recursive: true }).filter((n) => n.endsWith('.js'))
    expect(names).toContain('versions/engine-1.0.0.js') // every shipped version's rules, for the browser's verification
    for (const name of names) {
      const response = await server.api('GET', `/engine/${name}`)
      expect(response.status, name).toBe(200)
      expect(response.headers['content-type']).toMatch(/^text\/javascript/)
      expect(response.text).toBe(readFileSync(`${ENGINE_DIR}/${name}`, 'utf8'))
    }
    for (const url of ['/engine/nope.js', '/engine/..%2Fpackage.json', '/engine/../server/app.js', '/engine/versions/../../server/app.js', '/engine/versions/%2e%2e/%2e%2e/server/app.js', '/engine/versions/..%2F..%2Fpackage.json']) {
      expect((await server.api('GET', url)).status, url).toBe(404)
    }
  })

  for (const [prefix, dir, expected, what] of [
    ['protocol', PROTOCOL_DIR, ['snapshot-codec.js', 'room-id.js', 'client-messages.js'], 'every protocol file'],
    ['charts', CHARTS_DIR, ['svg.js'], 'the chart writer']
  ]) {
    it(`serves ${what} unchanged at /${prefix}/, and nothing else from there`, async () => {
      const names = readdirSync(dir).filter((n) => n.endsWith('.js'))
      expect(names).toEqual(expect.arrayContaining(expected))
      for (const name of names) {
        const response = await server.api('GET', `/${prefix}/${name}`)
        expect(response.status, name).toBe(200)
        expect(response.headers['content-type']).toMatch(/^text\/javascript/)
        expect(response.text).toBe(readFileSync(`${dir}/${name}`, 'utf8'))
      }
      for (const url of [`/${prefix}/nope.js`, `/${prefix}/..%2Fpackage.json`, `/${prefix}/../server/app.js`]) {
        expect((await server.api('GET', url)).status, url).toBe(404)
      }
    })
  }

  it('wraps seedrandom as an ES module that draws the same numbers as Node\'s', async () => {
    const response = await server.api('GET', '/vendor/seedrandom.js')
    expect(response.status).toBe(200)
    expect(response.headers['content-type']).toMatch(/^text\/javascript/)
    expect(response.text).toContain('export default module.exports')
    const module = await import(`data:text/javascript;base64,${Buffer.from(response.text).toString('base64')}`)
    const fromBrowserCopy = module.default('a drop seed')
    const fromNode = seedrandom('a drop seed')
    for (let i = 0; i < 100; i++) expect(fromBrowserCopy()).toBe(fromNode())
  })

  it('admits the inline import maps by hash, and no other inline script', async () => {
    const csp = (await server.api('GET', '/')).headers['content-security-policy']
    const scriptSrc = csp.split(';').map((d) => d.trim()).find((d) => d.startsWith('script-src '))
    expect(scriptSrc).toBeDefined()
    expect(scriptSrc).not.toContain('unsafe-inline')
    expect(scriptSrc).toContain("'self'")
    for (const file of ['index.html', 'audit.html']) {
      const html = readFileSync(`${CLIENT_DIR}/${file}`, 'utf8')
      const inline = [...html.matchAll(/<script type="importmap">([\s\S]*?)<\/script>/g)].map((m) => m[1])
      expect(inline, file).toHaveLength(1)
      expect(JSON.parse(inline[0])).toEqual({ imports: { seedrandom: '/vendor/seedrandom.js' } })
      expect(scriptSrc).toContain(`'sha256-${createHash('sha256').update(inline[0]).digest('base64')}'`)
    }
  })

  it('revalidates the shared modules by content hash: a 304 with no body while unchanged, never a stale copy', async () => {
    for (const url of ['/engine/index.js', '/protocol/payout.js', '/charts/svg.js', '/vendor/seedrandom.js']) {
      const first = await fetch(`${server.base}${url}`)
      const body = await first.text()
      const etag = first.headers.get('etag')
      expect(etag, url).toMatch(/^"[\w-]{22}"$/)
      expect(first.headers.get('cache-control')).toBe('no-cache')
      const again = await fetch(`${server.base}${url}`, { headers: { 'if-none-match': `"other", ${etag}` } })
      expect(again.status, url).toBe(304)
      expect(await again.text()).toBe('')
      const changed = await fetch(`${server.base}${url}`, { headers: { 'if-none-match': '"not-this-one"' } })
      expect(changed.status).toBe(200)
      expect(await changed.text()).toBe(body)
    }
    // Different files, different tags.
    const tags = await Promise.all(['/engine/index.js', '/engine/world.js'].map(async (url) => (await fetch(`${server.base}${url}`)).headers.get('etag')))
    expect(new Set(tags).size).toBe(2)
  })

  it('compresses the page and its modules for browsers that accept it, byte for byte the same once decoded', async () => {
    const { brotliDecompressSync, gunzipSync } = await import('node:zlib')
    const http = await import('node:http')
    // node:http, not fetch: fetch decodes on its own and hides what came over the wire.
    const raw = (url, encoding) => new Promise((resolve, reject) => {
      http.get(`${server.base}${url}`, { headers: { 'accept-encoding': encoding } }, (response) => {
        const chunks = []
        response.on('data', (chunk) => chunks.push(chunk))
        response.on('end', () => resolve({ headers: response.headers, body: Buffer.concat(chunks) }))
      }).on('error', reject)
    })
    for (const url of ['/', '/player.js', '/engine/world.js', '/protocol/snapshot-codec.js']) {
      const plain = await raw(url, 'identity')
      expect(plain.headers['content-encoding'], url).toBeUndefined()
      const br = await raw(url, 'br')
      expect(br.headers['content-encoding'], url).toBe('br')
      expect(brotliDecompressSync(br.body).equals(plain.body), url).toBe(true)
      expect(br.body.length, url).toBeLessThan(plain.body.length / 2)
      const gzip = await raw(url, 'gzip')
      expect(gzip.headers['content-encoding'], url).toBe('gzip')
      expect(gunzipSync(gzip.body).equals(plain.body), url).toBe(true)
    }
  })

  it('serves the player page in one module built from the very files it serves one by one', async () => {
    const page = await server.api('GET', '/')
    const scripts = [...page.text.matchAll(/<script\b[^>]*\bsrc="([^"]+)"/g)].map((m) => m[1])
    expect(scripts).toHaveLength(1)
    expect(scripts[0]).toMatch(/^\/bundle\/player\.js\?v=[\w-]{12}$/)
    const response = await fetch(`${server.base}${scripts[0]}`)
    expect(response.status).toBe(200)
    expect(response.headers.get('content-type')).toMatch(/^text\/javascript/)
    expect(response.headers.get('etag')).toMatch(/^"[\w-]{22}"$/)
    const bundle = await response.text()
    // Not minified: every module is there under its own path, the engine of every shipped version with it.
    const modules = [...bundle.matchAll(/^\/\/ (\S+\.js)$/gm)].map((m) => m[1])
    // The page's parts (client/player.js builds them) are in it too.
    expect(modules).toEqual(expect.arrayContaining(['client/room-connection.js', 'client/drop-results.js', 'client/bet-controls.js', 'client/auto-bet-controls.js', 'client/verification-view.js', 'client/render-loop.js', 'client/player-account.js', 'client/page-notices.js', 'client/page-probe.js']))
    expect(modules).toEqual(expect.arrayContaining(['client/player.js', 'engine/world.js', 'engine/versions/engine-1.0.0.js', 'engine/versions/engine-2.0.0.js', 'protocol/snapshot-codec.js', 'node_modules/seedrandom/seedrandom.js']))
    expect(bundle).not.toMatch(/^import\s/m) // nothing left to fetch
  })

  it('serves the worker that draws the board in one module too, and lets the pages start workers from this origin only', async () => {
    const page = await server.api('GET', '/')
    const [, url] = /<meta name="board-worker" content="([^"]+)">/.exec(page.text)
    expect(url).toMatch(/^\/bundle\/board-worker\.js\?v=[\w-]{12}$/)
    const response = await fetch(`${server.base}${url}`)
    expect(response.status).toBe(200)
    expect(response.headers.get('content-type')).toMatch(/^text\/javascript/)
    const bundle = await response.text()
    const modules = [...bundle.matchAll(/^\/\/ (\S+\.js)$/gm)].map((m) => m[1])
    expect(modules).toEqual(expect.arrayContaining(['client/board-worker.js', 'client/board-painter.js', 'client/board-geometry.js', 'client/pose-frame.js']))
    expect(bundle).not.toMatch(/^import\s/m)
    const csp = page.headers['content-security-policy'].split(';').map((d) => d.trim())
    expect(csp).toContain("worker-src 'self'")
  })
})
