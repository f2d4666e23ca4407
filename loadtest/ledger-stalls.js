#!/usr/bin/env node
/**
 * Disk stalls on demand, for a load test: holds a running server's SQLite
 * ledger's write lock for --hold every --every, for --duration, from a
 * connection of its own. The server's writer thread waits for it (its busy
 * timeout, 5 s), exactly as it waits for a slow fsync, so the ticks that
 * end meanwhile pile up behind one commit: what the group commit, the
 * replies and the room frames do after a stall of the disk can then be
 * measured on demand instead of waiting for the VM's disk to hiccup
 * (loadtest/RESULTS.md, "After a stall of the disk").
 *
 *   npm run loadtest:ledger-stalls -- --ledger /path/to/ledger.sqlite [--hold 400ms] [--every 4s] [--duration 60s]
 *
 * Writes nothing: each hold is BEGIN IMMEDIATE … ROLLBACK. Stops by itself
 * after --duration (or on SIGINT/SIGTERM, releasing the lock). Exit code 0,
 * 1 when the ledger cannot be opened or a stall fails (`E_LEDGER_STALLS`),
 * 2 for a bad command line.
 */
import fs from 'node:fs'
import { DatabaseSync } from 'node:sqlite'
import { setTimeout as sleep } from 'node:timers/promises'
import { pathToFileURL } from 'node:url'
import { parseCommandLine } from '../cli/command-line.js'
import { optionsOrExit } from '../cli/usage-error.js'
import { parseDuration, UsageError } from './driver/cli-args.js'

/** How long a hold waits for the lock itself (the server's writer holds it for a commit at a time). */
const BUSY_TIMEOUT_MS = 5000

export const USAGE = `usage: npm run loadtest:ledger-stalls -- --ledger FILE [options]

  --ledger FILE      the running server's SQLite ledger (DATABASE_URL=sqlite:FILE)
  --hold TIME        how long each stall holds the write lock (default 400ms)
  --every TIME       from the start of one stall to the next (default 4s)
  --duration TIME    stop after this (default 60s)
  -h, --help`

export class LedgerStallsError extends Error {
  constructor (message) {
    super(message)
    this.name = 'LedgerStallsError'
    this.code = 'E_LEDGER_STALLS'
  }
}

/** @param {string[]} argv */
export function parseLedgerStallsArgs (argv) {
  const values = parseCommandLine(argv, {
    help: { type: 'boolean', short: 'h' },
    ledger: { type: 'string' },
    hold: { type: 'string', default: '400ms' },
    every: { type: 'string', default: '4s' },
    duration: { type: 'string', default: '60s' }
  })
  if (values.help) return { help: true }
  if (!values.ledger) throw new UsageError('--ledger FILE is required')
  const holdMs = parseDuration(values.hold, 'hold') * 1000
  const everyMs = parseDuration(values.every, 'every') * 1000
  const durationMs = parseDuration(values.duration, 'duration') * 1000
  if (!(holdMs > 0)) throw new UsageError('--hold must be more than 0')
  if (!(everyMs > holdMs)) throw new UsageError('--every must be longer than --hold')
  return { ledger: values.ledger, holdMs, everyMs, durationMs }
}

/**
 * A connection to an existing ledger for holding its write lock. Refuses
 * (LedgerStallsError) a file that does not exist, rather than creating an
 * empty database beside the one the server writes.
 * @param {string} file
 */
export function openLedgerForStalls (file) {
  if (!fs.existsSync(file)) throw new LedgerStallsError(`no ledger at ${file}: start the server with DATABASE_URL=sqlite:${file} first`)
  try {
    const db = new DatabaseSync(file)
    db.exec(`PRAGMA busy_timeout = ${BUSY_TIMEOUT_MS}`)
    return db
  } catch (error) {
    throw new LedgerStallsError(`cannot open the ledger ${file}: ${error.message}`)
  }
}

/**
 * Holds the write lock of `db` for `holdMs`, then releases it without
 * writing. `onLocked` runs once the lock is held.
 * @param {import('node:sqlite').DatabaseSync} db
 * @param {number} holdMs
 * @param {{ onLocked?: () => void | Promise<void>, signal?: AbortSignal }} [options] signal: release early
 */
export async function stallLedger (db, holdMs, { onLocked, signal } = {}) {
  db.exec('BEGIN IMMEDIATE')
  try {
    await onLocked?.()
    await sleep(holdMs, undefined, { signal }).catch((error) => { if (error.name !== 'AbortError') throw error })
  } finally {
    db.exec('ROLLBACK')
  }
}

async function main () {
  const options = optionsOrExit(parseLedgerStallsArgs, process.argv.slice(2), USAGE)
  /** @param {LedgerStallsError} error */
  const refuse = (error) => {
    console.error(`${error.code}: ${error.message}`)
    process.exitCode = 1
  }
  let db
  try {
    db = openLedgerForStalls(options.ledger)
  } catch (error) {
    refuse(error)
    return
  }
  const stop = new AbortController()
  for (const signal of ['SIGINT', 'SIGTERM']) process.once(signal, () => stop.abort())
  const end = Date.now() + options.durationMs
  let stalls = 0
  while (!stop.signal.aborted && Date.now() + options.holdMs <= end) {
    const started = Date.now()
    try {
      await stallLedger(db, options.holdMs, { signal: stop.signal })
    } catch (error) {
      // The server went away with its file, or held the lock past the busy timeout.
      refuse(new LedgerStallsError(`stall ${stalls + 1} failed: ${error.message}`))
      break
    }
    stalls++
    console.log(`stall ${stalls}: held the write lock ${Date.now() - started} ms (waiting for it included)`)
    await sleep(Math.max(0, Math.min(end, started + options.everyMs) - Date.now()), undefined, { signal: stop.signal }).catch(() => {})
  }
  db.close()
  console.log(`ledger stalls: ${stalls} of ${options.holdMs} ms`)
}

if (import.meta.url === pathToFileURL(process.argv[1] ?? '').href) await main()
