import { createHash } from 'node:crypto'
import fs from 'node:fs'
import zlib from 'node:zlib'
import path from 'node:path'
import { createRequire } from 'node:module'
import { fileURLToPath } from 'node:url'
import { buildPageBundle } from './page-bundle.js'

/** Folders the browser runs as they are in the repository, by URL prefix: the engine, the wire format and the SVG chart writer. */
const SHARED_DIRS = {
  engine: fileURLToPath(new URL('../../engine/', import.meta.url)),
  protocol: fileURLToPath(new URL('../../protocol/', import.meta.url)),
  charts: fileURLToPath(new URL('../../charts/', import.meta.url))
}
const require = createRequire(import.meta.url)
/** What /vendor/seedrandom.js wraps: seedrandom's ARC4 generator, the function its index.js exports. */
const SEEDRANDOM_FILE = require.resolve('seedrandom/seedrandom.js')

/**
 * What the browser needs besides client/ to run the very same engine and
 * wire format as the server, with no build step:
 *   GET /engine/PATH.js        the repository's engine/ files (and engine/versions/), as they are
 *   GET /protocol/PATH.js      the repository's protocol/ files (frames, room ids, message schemas)
 *   GET /charts/PATH.js        the repository's charts/ files (the SVG writer the operator page's charts share with the CLI)
 *   GET /vendor/seedrandom.js  seedrandom as an ES module
 *   GET /bundle/player.js      the player page's whole module graph in one file (page-bundle.js)
 *   GET /bundle/board-worker.js the worker that draws its board (board-worker.js's modules, bundled alike)
 * and the pages themselves (/, /audit, /share/:id/:token), whose links to
 * the bundle, the stylesheet and the icon carry a version (?v=, a hash of
 * the file's content). The pages map the engine's one bare import,
 * 'seedrandom', to /vendor/seedrandom.js with an inline import map (see
 * inlineScriptHashes for how it passes the Content-Security-Policy).
 *
 * Caching: each file carries a strong ETag (its content hash). Asked for
 * under its current version it is `immutable` for a year (a repeat visit
 * asks nothing; a new deploy links a new version); otherwise, and the
 * pages themselves, `no-cache`: a bodiless 304 while unchanged, never a
 * stale engine. Compression: each file is compressed once per encoding
 * (Brotli, gzip), on its first request, and those bytes are kept, instead
 * of compressing every response afresh (@fastify/compress stays for the
 * API's replies).
 * @param {import('fastify').FastifyInstance} app
 * @param {{ clientDir: string }} options
 */
export default async function clientAssetRoutes (app, { clientDir }) {
  // Read once: a change needs a restart, like the server's own copy. Static
  // and cheap (compressed once), so outside the per-IP rate limit (a page load fetches every module).
  const asset = { config: { rateLimit: false }, compress: false }
  for (const [prefix, dir] of Object.entries(SHARED_DIRS)) {
    const files = new Map()
    for (const name of fs.readdirSync(dir, { recursive: true })) {
      if (name.endsWith('.js')) files.set(name.split(path.sep).join('/'), assetFile(fs.readFileSync(path.join(dir, name)), JS))
    }
    app.get(`/${prefix}/*`, { ...asset, schema: { summary: `A ${prefix} module, for the browser` } }, (request, reply) => {
      const file = request.params['*']
      const module = files.get(file)
      if (module === undefined) return reply.code(404).send({ code: 'E_NOT_FOUND', message: `no ${prefix} file ${file}` })
      return sendAsset(request, reply, module)
    })
  }
  const seedrandom = assetFile(seedrandomModule(), JS)

  app.get('/vendor/seedrandom.js', { ...asset, schema: { summary: 'seedrandom as an ES module, for the browser' } }, (request, reply) => {
    return sendAsset(request, reply, seedrandom)
  })

  // The files the pages link to with a version, and the pages with those links.
  const versioned = {}
  // The board's worker first: the player page links to it with its version (index.html's <meta name="board-worker">).
  for (const [url, name, summary] of [['/bundle/board-worker.js', 'board-worker.js', "The worker that draws the player page's board (its modules in one file)"], ['/bundle/player.js', 'player.js', "The player page's modules (engine, protocol, page) in one file"]]) {
    const entry = path.join(clientDir, name)
    if (!fs.existsSync(entry)) continue
    let bundle
    try {
      bundle = assetFile(await buildPageBundle(entry, { sharedDirs: SHARED_DIRS, seedrandom: SEEDRANDOM_FILE }), JS)
    } catch (error) {
      // The page still works, one module at a time, if the bundle cannot be built.
      app.log.error({ err: error }, `could not bundle ${name}; serving its modules one by one`)
      bundle = assetFile(`import '/${name}'\n`, JS)
    }
    versioned[url] = bundle
    app.get(url, { ...asset, schema: { summary } }, (request, reply) => sendAsset(request, reply, bundle))
  }

  for (const [url, name, type] of [['/style.css', 'style.css', 'text/css; charset=utf-8'], ['/favicon.svg', 'favicon.svg', 'image/svg+xml']]) {
    const file = path.join(clientDir, name)
    if (!fs.existsSync(file)) continue
    versioned[url] = assetFile(fs.readFileSync(file), type)
    app.get(url, { ...asset, schema: { summary: `The pages' ${name}` } }, (request, reply) => sendAsset(request, reply, versioned[url]))
  }
  for (const [url, name, summary] of [['/', 'index.html', 'The player page'], ['/audit', 'audit.html', 'Operator audit page'], ['/share/:id/:token', 'share.html', 'A shared drop, replayed and verified in the viewer\'s browser']]) {
    const file = path.join(clientDir, name)
    if (!fs.existsSync(file)) continue
    const page = assetFile(withVersions(fs.readFileSync(file, 'utf8'), versioned), 'text/html; charset=utf-8')
    app.get(url, { ...asset, schema: { summary } }, (request, reply) => sendAsset(request, reply, page))
  }
}

const JS = 'text/javascript; charset=utf-8'
/** A year: what `immutable` files may be kept for. */
const IMMUTABLE = 'public, max-age=31536000, immutable'

/** `html` with each quoted link to a versioned file given its version (?v=). @param {string} html @param {Record<string, ReturnType<typeof assetFile>>} versioned */
export function withVersions (html, versioned) {
  let out = html
  for (const [url, file] of Object.entries(versioned)) out = out.replaceAll(`"${url}"`, `"${url}?v=${file.version}"`)
  return out
}

/**
 * A file as served: its bytes, type, strong ETag and version (both from
 * its content hash), and its compressed forms, made on first use and kept.
 * @param {string | Buffer} content @param {string} type
 */
function assetFile (content, type) {
  const body = Buffer.isBuffer(content) ? content : Buffer.from(content, 'utf8')
  const hash = createHash('sha256').update(body).digest('base64url')
  /** @type {Record<string, Buffer>} */
  const encoded = {}
  return {
    body,
    type,
    etag: `"${hash.slice(0, 22)}"`,
    version: hash.slice(0, 12),
    /** The body in `encoding` ('br' or 'gzip'), compressed the first time it is asked for. @param {'br' | 'gzip'} encoding */
    encoded (encoding) {
      // Brotli 9: the 200 KB bundle in ~80 ms, once (11 would take 1.3 s for 9% less).
      encoded[encoding] ??= encoding === 'br'
        ? zlib.brotliCompressSync(body, { params: { [zlib.constants.BROTLI_PARAM_QUALITY]: 9, [zlib.constants.BROTLI_PARAM_SIZE_HINT]: body.length } })
        : zlib.gzipSync(body, { level: 9 })
      return encoded[encoding]
    }
  }
}

/** The encoding to send from Accept-Encoding: Brotli, else gzip, else none (q=0 refuses). @param {string | undefined} header */
function pickEncoding (header) {
  if (!header) return null
  const accepted = new Set()
  for (const part of header.split(',')) {
    const [name, ...params] = part.trim().toLowerCase().split(';')
    const q = params.map((p) => p.trim()).find((p) => p.startsWith('q='))
    if (q === undefined || Number(q.slice(2)) > 0) accepted.add(name)
  }
  if (accepted.has('br')) return 'br'
  if (accepted.has('gzip') || accepted.has('*')) return 'gzip'
  return null
}

/** The file (compressed as the browser accepts), or 304 when the browser's copy (If-None-Match) is this one. */
function sendAsset (request, reply, file) {
  const current = request.query?.v === file.version
  reply.type(file.type).header('cache-control', current ? IMMUTABLE : 'no-cache').header('etag', file.etag).header('vary', 'accept-encoding')
  const cached = request.headers['if-none-match']
  if (cached !== undefined && cached.split(',').some((tag) => tag.trim() === file.etag)) return reply.code(304).send()
  const encoding = pickEncoding(request.headers['accept-encoding'])
  if (encoding === null) return reply.send(file.body)
  return reply.header('content-encoding', encoding).send(file.encoded(encoding))
}

/**
 * seedrandom's ARC4 generator (node_modules/seedrandom/seedrandom.js, the
 * function its index.js exports, which the server's engine uses) wrapped as
 * an ES module. The file is a UMD: given an object `module`, it assigns
 * `module.exports = seedrandom`; its optional require('crypto'), used only
 * for autoseeding, sits in a try/catch and fails harmlessly because
 * `require` is undefined in the browser.
 */
export function seedrandomModule () {
  const file = SEEDRANDOM_FILE
  const source = fs.readFileSync(file, 'utf8')
  return `// seedrandom ${require('seedrandom/package.json').version} (${path.basename(file)}), wrapped as an ES module by server/routes/client-assets.js\n` +
    'const module = { exports: {} };\n' +
    source +
    '\nexport default module.exports;\n'
}

/**
 * CSP hash sources ('sha256-…') of every inline <script> in the client's
 * HTML pages: only the import maps, which browsers check against
 * script-src like any inline script. app.js adds them to helmet's
 * script-src, so the policy stays "scripts from this origin only" without
 * 'unsafe-inline'. A missing client folder yields none.
 * @param {string} clientDir
 * @returns {string[]}
 */
export function inlineScriptHashes (clientDir) {
  let names
  try {
    names = fs.readdirSync(clientDir).filter((name) => name.endsWith('.html'))
  } catch {
    return []
  }
  const hashes = new Set()
  for (const name of names) {
    const html = fs.readFileSync(path.join(clientDir, name), 'utf8')
    for (const match of html.matchAll(/<script\b[^>]*>([\s\S]*?)<\/script>/gi)) {
      if (/\bsrc\s*=/.test(match[0].slice(0, match[0].indexOf('>')))) continue
      hashes.add(`'sha256-${createHash('sha256').update(match[1], 'utf8').digest('base64')}'`)
    }
  }
  return [...hashes].sort()
}
