import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { spawn, spawnSync } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { OPERATOR_TOKEN } from '../server/helpers/server.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')
/** A mount namespace of our own (unshare -rm) makes a read-only bind mount without touching the machine's. */
const canUnshare = spawnSync('unshare', ['-rm', 'true']).status === 0

/**
 * `node server/server.js` on a SQLite file whose directory is mounted
 * read-only (a bind mount inside its own mount namespace: root included,
 * nobody can write there). Resolves with its exit code and output.
 */
function startOnReadOnly (directory, file) {
  const script = 'mount --bind "$DATA_DIR" "$DATA_DIR" && mount -o remount,bind,ro "$DATA_DIR" && exec "$NODE" server/server.js'
  const child = spawn('unshare', ['-rm', 'sh', '-c', script], {
    cwd: ROOT,
    env: { ...process.env, DATA_DIR: directory, NODE: process.execPath, DATABASE_URL: `sqlite:${file}`, OPERATOR_TOKEN, PORT: '0', HOST: '127.0.0.1', LOG_FORMAT: 'json' },
    stdio: ['ignore', 'pipe', 'pipe']
  })
  let output = ''
  child.stdout.on('data', (chunk) => { output += chunk })
  child.stderr.on('data', (chunk) => { output += chunk })
  return new Promise((resolve) => child.once('exit', (code) => resolve({ code, output })))
}

/** Issue #21, item 8: a read-only data directory said only "unable to open database file". */
describe.skipIf(!canUnshare)('a read-only data directory at start', () => {
  let directory
  beforeAll(() => { directory = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-readonly-')) })
  afterAll(() => fs.rmSync(directory, { recursive: true, force: true }))

  it('is named as the cause, for a new database file and for an existing one', async () => {
    const fresh = await startOnReadOnly(directory, path.join(directory, 'plinko.sqlite'))
    expect(fresh.code).toBe(1)
    expect(fresh.output).toContain(`plinko server failed to start: the data directory ${directory} is on a read-only file system`)
    expect(fresh.output).not.toContain('unable to open database file')

    // An existing ledger on a read-only directory: the same (WAL needs its -wal and -shm files there).
    fs.writeFileSync(path.join(directory, 'existing.sqlite'), '')
    const existing = await startOnReadOnly(directory, path.join(directory, 'existing.sqlite'))
    expect(existing.code).toBe(1)
    expect(existing.output).toContain(`the data directory ${directory} is on a read-only file system`)
  })

  it('names a data path under a file (not a directory)', async () => {
    const notDirectory = path.join(directory, 'a-file')
    fs.writeFileSync(notDirectory, '')
    const child = spawnSync(process.execPath, ['server/server.js'], {
      cwd: ROOT,
      env: { ...process.env, DATABASE_URL: `sqlite:${notDirectory}/plinko.sqlite`, OPERATOR_TOKEN, PORT: '0', HOST: '127.0.0.1', LOG_FORMAT: 'json' },
      encoding: 'utf8',
      timeout: 20_000
    })
    expect(child.status).toBe(1)
    expect(child.stderr).toContain(`the data directory ${notDirectory} is not a directory`)
  })
})
