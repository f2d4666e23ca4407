import { describe, it, expect, afterEach } from 'vitest'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { spawnSync } from 'node:child_process'
import { fileURLToPath } from 'node:url'
import { DatabaseSync } from 'node:sqlite'
import { parseLedgerStallsArgs, openLedgerForStalls, stallLedger, LedgerStallsError } from '../../loadtest/ledger-stalls.js'
import { UsageError } from '../../cli/usage-error.js'

const SCRIPT = fileURLToPath(new URL('../../loadtest/ledger-stalls.js', import.meta.url))
const dirs = []
afterEach(() => { for (const dir of dirs.splice(0)) fs.rmSync(dir, { recursive: true, force: true }) })

/** A WAL database with one row, as a server's ledger is. */
function walLedger () {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-stalls-'))
  dirs.push(dir)
  const file = path.join(dir, 'ledger.sqlite')
  const db = new DatabaseSync(file)
  db.exec('PRAGMA journal_mode = WAL; CREATE TABLE t (v INTEGER); INSERT INTO t VALUES (1)')
  return { file, db }
}

describe('loadtest/ledger-stalls.js', () => {
  it('holds the write lock while it stalls: another writer is refused, readers are not, and nothing is written', async () => {
    const { file, db: writer } = walLedger()
    writer.exec('PRAGMA busy_timeout = 0')
    const stalls = openLedgerForStalls(file)
    const seen = []
    await stallLedger(stalls, 1, {
      onLocked () {
        expect(() => writer.exec('BEGIN IMMEDIATE')).toThrow(/locked|busy/i)
        seen.push(writer.prepare('SELECT v FROM t').get().v)
      }
    })
    expect(seen).toEqual([1])
    writer.exec('BEGIN IMMEDIATE; UPDATE t SET v = 2; COMMIT')
    expect(writer.prepare('SELECT v FROM t').get().v).toBe(2)
    stalls.close()
    writer.close()
  })

  it('releases the lock early when aborted', async () => {
    const { file, db: writer } = walLedger()
    const stalls = openLedgerForStalls(file)
    const stop = new AbortController()
    let locked = false
    const held = stallLedger(stalls, 60_000, { signal: stop.signal, onLocked: () => { locked = true; stop.abort() } })
    await held
    expect(locked).toBe(true)
    writer.exec('PRAGMA busy_timeout = 0; BEGIN IMMEDIATE; COMMIT')
    stalls.close()
    writer.close()
  })

  it('refuses a ledger that does not exist instead of creating one', () => {
    const missing = path.join(os.tmpdir(), `plinko-no-ledger-${process.pid}.sqlite`)
    expect(() => openLedgerForStalls(missing)).toThrow(LedgerStallsError)
    expect(fs.existsSync(missing)).toBe(false)
    const run = spawnSync(process.execPath, [SCRIPT, '--ledger', missing], { encoding: 'utf8' })
    expect(run.status).toBe(1)
    expect(run.stderr).toMatch(/E_LEDGER_STALLS: no ledger at/)
  })

  it('ends with E_LEDGER_STALLS (exit code 1) when the file is not an SQLite ledger', () => {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-stalls-'))
    dirs.push(dir)
    const file = path.join(dir, 'notes.txt')
    fs.writeFileSync(file, 'not a database, and long enough to have a header\n'.repeat(4))
    const run = spawnSync(process.execPath, [SCRIPT, '--ledger', file, '--hold', '20ms', '--every', '50ms', '--duration', '100ms'], { encoding: 'utf8', timeout: 30_000 })
    expect(run.status).toBe(1)
    expect(run.stderr).toMatch(/E_LEDGER_STALLS: .*not a database/)
  })

  it('reads its options, with defaults, and refuses bad ones with the usage (exit code 2)', () => {
    expect(parseLedgerStallsArgs(['--ledger', 'x.sqlite'])).toEqual({ ledger: 'x.sqlite', holdMs: 400, everyMs: 4000, durationMs: 60000 })
    expect(parseLedgerStallsArgs(['--ledger', 'x', '--hold', '1s', '--every', '3s', '--duration', '10s'])).toMatchObject({ holdMs: 1000, everyMs: 3000, durationMs: 10000 })
    expect(() => parseLedgerStallsArgs([])).toThrow(UsageError)
    expect(() => parseLedgerStallsArgs(['--ledger', 'x', '--hold', '5s', '--every', '4s'])).toThrow(/--every must be longer/)
    expect(() => parseLedgerStallsArgs(['--ledger', 'x', '--hold', '0ms'])).toThrow(/--hold/)
    const run = spawnSync(process.execPath, [SCRIPT, '--hold', 'soon'], { encoding: 'utf8' })
    expect(run.status).toBe(2)
    expect(run.stderr).toMatch(/usage: npm run loadtest:ledger-stalls/)
  })

  it('stops by itself after --duration, having stalled the ledger', () => {
    const { file, db } = walLedger()
    const run = spawnSync(process.execPath, [SCRIPT, '--ledger', file, '--hold', '20ms', '--every', '50ms', '--duration', '130ms'], { encoding: 'utf8', timeout: 30_000 })
    expect(run.status).toBe(0)
    expect(run.stdout).toMatch(/ledger stalls: [1-3] of 20 ms/)
    expect(db.prepare('SELECT v FROM t').get().v).toBe(1)
    db.close()
  })
})
