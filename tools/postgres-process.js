import { execFileSync } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import pg from 'pg'
import { freePort } from './free-port.js'

/**
 * A throwaway PostgreSQL server for the tests: `initdb` a cluster in a temp
 * dir, `pg_ctl start` it on a free loopback port (unix socket in the same
 * dir), hand out fresh databases, and `pg_ctl stop -m immediate` + delete
 * everything at the end. initdb and pg_ctl must be on PATH (PostgreSQL 15
 * here). PostgreSQL refuses to run as root, so as root the cluster belongs
 * to the `postgres` system user (PLINKO_TEST_PG_USER to pick another) and
 * the commands run through `runuser -u USER --`; the user is created with
 * `useradd --system` if it does not exist.
 *
 * Set PLINKO_TEST_POSTGRES_URL (e.g. postgres://postgres@127.0.0.1:5432/postgres,
 * a role allowed to CREATE DATABASE) to use an existing server instead.
 *
 * Durability settings (fsync, synchronous_commit) are off: the cluster is
 * deleted after the run, and the tests check behaviour, not crash safety of
 * PostgreSQL itself. `durable: true` keeps PostgreSQL's own (every commit
 * flushed), for measurements whose latencies must include the flush.
 * @param {{ durable?: boolean }} [options]
 */
export async function startPostgres ({ durable = false } = {}) {
  const existing = process.env.PLINKO_TEST_POSTGRES_URL
  if (existing) return serverAt(existing, async () => {})

  const asRoot = process.getuid?.() === 0
  const user = process.env.PLINKO_TEST_PG_USER ?? 'postgres'
  if (asRoot) ensureUser(user)
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-pg-'))
  const dataDir = path.join(dir, 'data')
  if (asRoot) execFileSync('chown', [user, dir])
  const run = (command, args) => asRoot
    ? execFileSync('runuser', ['-u', user, '--', command, ...args], { stdio: 'pipe' })
    : execFileSync(command, args, { stdio: 'pipe' })

  let started = false
  const stop = () => {
    if (started) {
      started = false
      try { run('pg_ctl', ['-D', dataDir, '-m', 'immediate', '-w', 'stop']) } catch {}
    }
    fs.rmSync(dir, { recursive: true, force: true })
  }
  // If the test process dies without afterAll, do not leave a server behind.
  process.once('exit', stop)
  try {
    run('initdb', ['-D', dataDir, '-U', 'postgres', '--auth=trust', '-E', 'UTF8', '--no-sync', '--locale=C'])
    const port = await freePort()
    run('pg_ctl', ['-D', dataDir, '-l', path.join(dir, 'postgres.log'), '-w', '-t', '60', '-o',
      `-p ${port} -k ${dir} -c listen_addresses=127.0.0.1${durable ? '' : ' -c fsync=off -c synchronous_commit=off -c full_page_writes=off'}`,
      'start'])
    started = true
    return serverAt(`postgres://postgres@127.0.0.1:${port}/postgres`, async () => {
      process.removeListener('exit', stop)
      stop()
    })
  } catch (error) {
    const log = path.join(dir, 'postgres.log')
    const detail = fs.existsSync(log) ? fs.readFileSync(log, 'utf8').slice(-2000) : ''
    stop()
    throw new Error(`could not start PostgreSQL for the tests: ${error.stderr?.toString() || error.message}\n${detail}`)
  }
}

/**
 * @param {string} adminUrl @param {() => Promise<void>} stop
 * @returns {{ adminUrl: string, createDatabase: () => Promise<string>, stop: () => Promise<void> }}
 */
function serverAt (adminUrl, stop) {
  let count = 0
  return {
    adminUrl,
    /** A new empty database; returns its URL. */
    async createDatabase () {
      const name = `plinko_test_${process.pid}_${Date.now().toString(36)}_${count++}`
      const client = new pg.Client({ connectionString: adminUrl })
      await client.connect()
      try {
        await client.query(`CREATE DATABASE ${name}`)
      } finally {
        await client.end()
      }
      const url = new URL(adminUrl)
      url.pathname = '/' + name
      return url.toString()
    },
    stop
  }
}

function ensureUser (user) {
  try {
    execFileSync('id', ['-u', user], { stdio: 'pipe' })
  } catch {
    execFileSync('useradd', ['--system', '--no-create-home', '--shell', '/usr/sbin/nologin', user], { stdio: 'pipe' })
  }
}

