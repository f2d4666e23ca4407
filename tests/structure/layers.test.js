import { describe, it, expect } from 'vitest'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { sourceFiles, importsOf, longFunctions } from './source-tree.js'

/**
 * The tree's shape, checked on every file: which folder may import which
 * (layers point down, nothing ships depending on a dev folder, nothing
 * outside tests/ reaches into tests/), and how long a function may grow.
 */
const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')
const FILES = sourceFiles(ROOT)

/** What each shipped folder may import, besides itself and Node's built-ins ('npm': any installed package). */
const MAY_IMPORT = {
  engine: ['seedrandom'],
  protocol: ['engine'],
  charts: [],
  cli: ['engine', 'protocol', 'charts'],
  bin: ['cli'],
  client: ['engine', 'protocol', 'charts', 'vendor'],
  server: ['engine', 'protocol', 'charts', 'npm']
}

/**
 * The server's layers, lowest first: a module imports only from its own
 * layer or those below (server/app.js is the composition root, server.js
 * only starts it). The base files are what every layer may use.
 */
const SERVER_BASE = ['errors.js', 'config.js', 'log-format.js', 'operator-token-strength.js', 'metrics.js', 'auth.js', 'start-banner.js']
const SERVER_LAYERS = [
  ['fairness'], // seeds and their hashes
  ['limits'], // token buckets, per-address budgets, connection caps
  ['store'], // the ledger: SQLite, PostgreSQL, the contract
  ['rooms'], // boards, a room's simulator, the clock
  ['game'], // accounts, drops, money, the group commit, seed changes, recovery
  ['coordination', 'cluster'], // one process or many: ownership, sequences, the shared ledger
  ['realtime'], // one WebSocket connection and how it is fed
  ['arena.js'], // the rooms on one clock, the game's face to a connection
  ['routes'], // HTTP
  ['app.js'],
  ['server.js']
]

/** A function over this many lines is split, except the engine's inlined hot loop (its comment says why). */
const MAX_FUNCTION_LINES = 80
const LONG_ON_PURPOSE = new Set(['engine/world.js _advanceBodies'])
/** Known before this test existed, to be split (#22); the list may only shrink. */
const KNOWN_LONG = new Set([])

const folderOf = (specifier) => specifier.split('/')[0]
const isBuiltin = (specifier) => specifier.startsWith('node:')
const isPackage = (specifier) => !specifier.includes('/') || specifier.startsWith('@') || !/\.m?js$/.test(specifier)

describe('the source tree', () => {
  it('finds the files and their imports', () => {
    expect(FILES.length).toBeGreaterThan(200)
    expect(importsOf('server/a/b.js', "import x from '../c.js'\nconst y = await import('./d.js')\nexport { z } from 'pg'")).toEqual(['server/c.js', 'server/a/d.js', 'pg'])
    expect(importsOf('client/p.js', "import { a } from '/engine/index.js'")).toEqual(['engine/index.js'])
    expect(longFunctions('function f () {\n' + '  x()\n'.repeat(90) + '}\n', 80)).toEqual([{ name: 'f', line: 1, lines: 92 }])
    expect(longFunctions('function f () {\n  x()\n}\n', 80)).toEqual([])
  })

  it('has layers that point down: each shipped folder imports only what is below it', () => {
    const wrong = []
    for (const { file, text } of FILES) {
      const folder = folderOf(file)
      const allowed = MAY_IMPORT[folder]
      if (!allowed) continue
      for (const specifier of importsOf(file, text)) {
        if (isBuiltin(specifier)) continue
        if (isPackage(specifier)) {
          if (!allowed.includes('npm') && !allowed.includes(specifier)) wrong.push(`${file} → ${specifier}`)
          continue
        }
        const target = folderOf(specifier)
        if (target !== folder && !allowed.includes(target)) wrong.push(`${file} → ${specifier}`)
      }
    }
    expect(wrong).toEqual([])
  })

  it('has server layers that point down: no module imports a layer above its own', () => {
    const unit = (file) => file.split('/')[1]
    const layerOf = (file) => {
      const name = unit(file)
      if (SERVER_BASE.includes(name)) return -1
      const layer = SERVER_LAYERS.findIndex((units) => units.includes(name))
      if (layer === -1) throw new Error(`${file}: server/${name} is in no layer of this test`)
      return layer
    }
    const wrong = []
    for (const { file, text } of FILES.filter(({ file }) => file.startsWith('server/'))) {
      for (const specifier of importsOf(file, text).filter((s) => s.startsWith('server/'))) {
        if (layerOf(specifier) > layerOf(file)) wrong.push(`${file} → ${specifier}`)
      }
    }
    expect(wrong).toEqual([])
    expect(layerOf('server/routes/x.js')).toBeGreaterThan(layerOf('server/game/x.js'))
  })

  it('has nothing outside tests/ importing tests/', () => {
    const wrong = FILES.filter(({ file }) => !file.startsWith('tests/'))
      .flatMap(({ file, text }) => importsOf(file, text).filter((s) => s.startsWith('tests/')).map((s) => `${file} → ${s}`))
    expect(wrong).toEqual([])
  })

  it(`has no function over ${MAX_FUNCTION_LINES} lines but the engine's hot loop (and the known ones, which may only go)`, () => {
    const long = FILES.flatMap(({ file, text }) => longFunctions(text, MAX_FUNCTION_LINES).map((f) => `${file} ${f.name}`))
      .filter((name) => !LONG_ON_PURPOSE.has(name))
    expect(long.filter((name) => !KNOWN_LONG.has(name))).toEqual([])
    // A known one that was split leaves the list.
    expect([...KNOWN_LONG].filter((name) => !long.includes(name))).toEqual([])
  })
})
