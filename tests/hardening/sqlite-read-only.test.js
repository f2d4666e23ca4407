import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { execFileSync } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { DatabaseSync } from 'node:sqlite'
import { SqliteStore } from '../../server/store/sqlite-store.js'
import { startServerProcess } from './helpers/server-process.js'

/**
 * The SQLite ledger in a directory the server cannot write (a read-only
 * volume, wrong owner): the server does not start, exits 1 with one line
 * naming the directory, the cause and what SQLite keeps there (the file and,
 * for the WAL journal, its -wal and -shm), and the ledger is untouched: once the directory
 * is writable again the same ledger opens with everything in it.
 *
 * A read-only directory is made with chmod where that binds (not root), or
 * as a read-only tmpfs where the tests run as root (root ignores modes);
 * where neither is possible the test is skipped, saying why.
 */
const root = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-read-only-'))
const dir = path.join(root, 'volume')
fs.mkdirSync(dir)

/** Makes `dir` read-only and returns how to undo it, or null where this process cannot. */
function readOnly () {
  if (process.getuid?.() !== 0) {
    fs.chmodSync(dir, 0o555)
    return () => fs.chmodSync(dir, 0o755)
  }
  try {
    execFileSync('mount', ['-o', 'remount,ro', dir], { stdio: 'ignore' })
    return () => execFileSync('mount', ['-o', 'remount,rw', dir], { stdio: 'ignore' })
  } catch {
    return null
  }
}

let mounted = false
if (process.getuid?.() === 0) {
  try {
    execFileSync('mount', ['-t', 'tmpfs', '-o', 'size=16m', 'tmpfs', dir], { stdio: 'ignore' })
    mounted = true
  } catch {}
}
const possible = process.getuid?.() !== 0 || mounted

const file = path.join(dir, 'ledger.sqlite')
const player = { id: 'p1', tokenHash: 'h1', balance: 5000, clientSeed: 'c', createdAt: 1, seed: { id: 's1', seed: 'a'.repeat(64), hash: 'b'.repeat(64) } }

beforeAll(async () => {
  if (!possible) return
  const store = new SqliteStore({ file })
  await store.migrate()
  await store.createPlayer(player)
  await store.close()
})

afterAll(() => {
  if (mounted) execFileSync('umount', [dir], { stdio: 'ignore' })
  fs.rmSync(root, { recursive: true, force: true })
})

describe.skipIf(!possible)('SQLite ledger in a read-only directory (needs a non-root user, or root allowed to mount a tmpfs)', () => {
  it('refuses to start with one line naming the file and the cause, and leaves the ledger as it was', async () => {
    const undo = readOnly()
    expect(undo, 'the directory could be made read-only').not.toBeNull()
    const attempts = []
    try {
      for (const ledger of [file, path.join(dir, 'new.sqlite')]) {
        const server = startServerProcess(`sqlite:${ledger}`)
        server.port.catch(() => {})
        attempts.push({ ledger, exit: await server.exited, output: server.output() })
      }
    } finally {
      undo()
    }
    for (const { ledger, exit, output } of attempts) {
      expect(exit).toEqual({ code: 1, signal: null })
      const lines = output.trim().split('\n').filter((line) => !line.includes('OPERATOR_TOKEN not set'))
      expect(lines).toHaveLength(1)
      // The data directory's check (server/store/data-directory.js) names it before SQLite is asked.
      expect(lines[0]).toMatch(/^plinko server failed to start: /)
      expect(lines[0]).toContain(`the data directory ${dir} `)
      expect(lines[0]).toMatch(/is on a read-only file system|is not writable by this process/)
      expect(lines[0]).toContain(`SQLite keeps ${path.basename(ledger)} and its -wal and -shm files there`)
    }
    expect(fs.existsSync(path.join(dir, 'new.sqlite'))).toBe(false)

    // Writable again: the same ledger opens, with its player.
    const server = startServerProcess(`sqlite:${file}`)
    try {
      const port = await server.port
      expect((await (await fetch(`http://127.0.0.1:${port}/api/health`)).json()).store).toBe('sqlite')
    } finally {
      server.child.kill('SIGTERM')
      await server.exited
    }
    const db = new DatabaseSync(file, { readOnly: true })
    try {
      expect(db.prepare('SELECT id, balance FROM players').all()).toEqual([{ id: 'p1', balance: 5000 }])
    } finally {
      db.close()
    }
  })
})
