import { createHash } from 'node:crypto'
import fs from 'node:fs'
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
 * The pages map the engine's one bare import, 'seedrandom', to
 * /vendor/seedrandom.js with an inline import map (see inlineScriptHashes
 * for how it passes the Content-Security-Policy). Each file carries a strong
 * ETag (its content hash) and `no-cache`: a browser revalidates and gets a
 * bodiless 304 while the file is unchanged, and a new engine the moment it
 * is deployed, never a stale one.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ clientDir: string }} options
 */
export default async function clientAssetRoutes (app, { clientDir }) {
  // Read once: a change needs a restart, like the server's own copy. Static
  // and cheap, so outside the per-IP rate limit (a page load fetches every module).
  for (const [prefix, dir] of Object.entries(SHARED_DIRS)) {
    const files = new Map()
    for (const name of fs.readdirSync(dir, { recursive: true })) {
      if (name.endsWith('.js')) files.set(name.split(path.sep).join('/'), moduleFile(fs.readFileSync(path.join(dir, name), 'utf8')))
    }
    app.get(`/${prefix}/*`, { config: { rateLimit: false }, schema: { summary: `A ${prefix} module, for the browser` } }, (request, reply) => {
      const file = request.params['*']
      const module = files.get(file)
      if (module === undefined) return reply.code(404).send({ code: 'E_NOT_FOUND', message: `no ${prefix} file ${file}` })
      return sendModule(request, reply, module)
    })
  }
  const seedrandom = moduleFile(seedrandomModule())

  app.get('/vendor/seedrandom.js', { config: { rateLimit: false }, schema: { summary: 'seedrandom as an ES module, for the browser' } }, (request, reply) => {
    return sendModule(request, reply, seedrandom)
  })

  const entry = path.join(clientDir, 'player.js')
  if (!fs.existsSync(entry)) return
  let bundle
  try {
    bundle = moduleFile(await buildPageBundle(entry, { sharedDirs: SHARED_DIRS, seedrandom: SEEDRANDOM_FILE }))
  } catch (error) {
    // The page still works, one module at a time, if the bundle cannot be built.
    app.log.error({ err: error }, 'could not bundle the player page; serving its modules one by one')
    bundle = moduleFile("import '/player.js'\n")
  }
  app.get('/bundle/player.js', { config: { rateLimit: false }, schema: { summary: "The player page's modules (engine, protocol, page) in one file" } }, (request, reply) => {
    return sendModule(request, reply, bundle)
  })
}

/** A module's source and its strong ETag. @param {string} source */
function moduleFile (source) {
  return { source, etag: `"${createHash('sha256').update(source, 'utf8').digest('base64url').slice(0, 22)}"` }
}

/** The module, or 304 when the browser's copy (If-None-Match) is this one. */
function sendModule (request, reply, { source, etag }) {
  reply.type('text/javascript; charset=utf-8').header('cache-control', 'no-cache').header('etag', etag)
  const cached = request.headers['if-none-match']
  if (cached !== undefined && cached.split(',').some((tag) => tag.trim() === etag)) return reply.code(304).send()
  return reply.send(source)
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
