import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { execFileSync } from 'node:child_process'
import fs from 'node:fs'
import { DatabaseSync } from 'node:sqlite'
import os from 'node:os'
import path from 'node:path'
import { GameClient } from '../server/helpers/game-client.js'
import { startServerProcess } from './helpers/server-process.js'
import { expectConsistentLedger } from './helpers/ledger.js'
import { DISK_RESERVE_BYTES } from '../../server/store/disk-reserve.js'

/**
 * A real full disk under the SQLite ledger: an 8 MB tmpfs that a filler
 * file keeps full (it takes back every byte freed, like a runaway log) for
 * as long as the fault lasts.
 * - Payouts that could not be written are retried until they are, without
 *   a restart, and /api/health says `degraded` meanwhile.
 * - SIGTERM during the fault: the last log line counts the unsettled drops
 *   and the exit code is 1.
 * - A process killed on a full disk starts again on it (the reserve file
 *   is given back at start) and its recovery settles what was in flight.
 * Needs root (mount); skipped with a message otherwise.
 */
const DISK_SIZE = '8m'
const BALLS = 30

function mountSmallDisk () {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-small-disk-'))
  try {
    execFileSync('mount', ['-t', 'tmpfs', '-o', `size=${DISK_SIZE}`, 'tmpfs', dir], { stdio: 'pipe' })
    return dir
  } catch (error) {
    fs.rmSync(dir, { recursive: true, force: true })
    console.warn(`[storage-fault] skipped: cannot mount a ${DISK_SIZE} tmpfs (${String(error.stderr || error.message).trim()}); run as root`)
    return null
  }
}

/** Fills the disk and, while started, keeps it full: every byte freed is taken back within 5 ms. */
class DiskFiller {
  constructor (dir) {
    this.file = path.join(dir, 'filler')
    this.timer = null
  }

  start () {
    this.fill()
    this.timer = setInterval(() => this.fill(), 5)
    return this
  }

  fill () {
    const fd = fs.openSync(this.file, 'a')
    try {
      for (const size of [256 * 1024, 4096, 512]) {
        const chunk = Buffer.alloc(size)
        for (;;) {
          try {
            if (fs.writeSync(fd, chunk) < size) break
          } catch (error) {
            if (error.code === 'ENOSPC') break
            throw error
          }
        }
      }
    } finally {
      fs.closeSync(fd)
    }
  }

  /** Stops refilling; with `remove`, the space comes back. */
  stop ({ remove = true } = {}) {
    clearInterval(this.timer)
    if (remove) fs.rmSync(this.file, { force: true })
  }
}

const until = async (condition, what, timeoutMs = 20_000) => {
  const deadline = Date.now() + timeoutMs
  for (;;) {
    const value = await condition()
    if (value) return value
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${what}`)
    await new Promise((resolve) => setTimeout(resolve, 20))
  }
}

const health = async (port) => (await fetch(`http://127.0.0.1:${port}/api/health`)).json()

async function player (port) {
  const session = await (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
  const client = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
  client.send({ type: 'join', room: '16-high' })
  await client.take('joined')
  return { session, client }
}

/** Sends `count` drops and waits for each to be recorded (acknowledged). */
async function dropAndWait ({ client }, count) {
  const before = client.messages.filter((m) => m.type === 'dropped' && m.player === client.welcome.playerId).length
  for (let i = 0; i < count; i++) client.send({ type: 'drop', bet: 10 })
  await until(() => client.messages.filter((m) => m.type === 'dropped' && m.player === client.welcome.playerId).length === before + count, 'the drops to be recorded')
}

const settledCount = ({ client }) => client.messages.filter((m) => m.type === 'settled' && m.player === client.welcome.playerId).length

const disk = mountSmallDisk()

describe.skipIf(!disk)('storage fault: SQLite on a full disk', () => {
  // Each test starts on a fresh ledger: its WAL must grow to commit (a WAL that was reset is rewritten in place).
  let file = null
  const backend = {
    async query (_, sql, params = []) {
      const db = new DatabaseSync(file, { readOnly: true })
      try { return db.prepare(sql.replace(/\$\d+/g, '?')).all(...params) } finally { db.close() }
    }
  }
  let playerIds = []
  let proc = null
  let filler = null

  afterAll(() => {
    filler?.stop()
    proc?.child.kill('SIGKILL')
    execFileSync('umount', ['-l', disk])
    fs.rmSync(disk, { recursive: true, force: true })
  })

  it('retries payouts until the disk has room again, degraded meanwhile, without a restart', async () => {
    file = path.join(disk, 'ledger-1.sqlite')
    proc = startServerProcess(`sqlite:${file}`, { DROP_RATE: '100', DROP_BURST: '100', SHUTDOWN_TIMEOUT_MS: '3000' })
    const port = await proc.port
    const one = await player(port)
    playerIds.push(one.session.playerId)
    expect((await health(port)).status).toBe('ok')
    // The reserve is made by the first writes.
    await until(() => fs.existsSync(`${file}.reserve`), 'the reserve file')

    await dropAndWait(one, BALLS)
    expect(settledCount(one)).toBeLessThan(BALLS)
    filler = new DiskFiller(disk).start()
    const fault = Date.now()
    const degraded = await until(async () => { const h = await health(port); return h.status === 'degraded' && h }, '/api/health to say degraded')
    expect(degraded.settlementsWaiting).toBeGreaterThan(0)
    const waitingMetric = async () => Number(/^plinko_settlements_waiting (\d+)/m.exec(await (await fetch(`http://127.0.0.1:${port}/metrics`)).text())[1])
    expect(await waitingMetric()).toBeGreaterThan(0)
    // A few seconds of fault: the retries keep failing meanwhile (far longer than 5 consecutive commits).
    await until(() => Date.now() - fault > 4000, 'the fault to last 4 s', 10_000)
    expect(settledCount(one)).toBeLessThan(BALLS)
    expect((await health(port)).status).toBe('degraded')
    filler.stop()
    const freed = Date.now()
    await until(() => settledCount(one) === BALLS, 'every payout after the space came back')
    console.info(`[storage-fault] ${BALLS} drops, disk full for ${freed - fault} ms: ${degraded.settlementsWaiting}+ payouts waited, all ${BALLS} paid ${Date.now() - freed} ms after the space came back, no restart`)
    expect(await health(port)).toMatchObject({ status: 'ok', settlementsWaiting: 0 })
    expect(await waitingMetric()).toBe(0)
    expect(proc.output()).not.toMatch(/until restart/)
    await expectConsistentLedger(expect, backend, null, { playerIds, startingBalance: 100000 })
    // The reserve is made again once there is room (it was given to the retries).
    await until(async () => { await dropAndWait(one, 1); return fs.existsSync(`${file}.reserve`) }, 'the reserve to be made again')
    await until(() => settledCount(one) === one.client.messages.filter((m) => m.type === 'dropped' && m.player === one.client.welcome.playerId).length, 'the last drops to settle')
    await one.client.close()
    proc.child.kill('SIGTERM')
    expect(await proc.exited).toEqual({ code: 0, signal: null })
    for (const name of fs.readdirSync(disk)) fs.rmSync(path.join(disk, name))
  }, 60_000)

  it('SIGTERM during the fault: the last line counts the unsettled drops, exit code 1', async () => {
    file = path.join(disk, 'ledger-2.sqlite')
    proc = startServerProcess(`sqlite:${file}`, { DROP_RATE: '100', DROP_BURST: '100', SHUTDOWN_TIMEOUT_MS: '3000' })
    const port = await proc.port
    const one = await player(port)
    playerIds = [one.session.playerId]
    await dropAndWait(one, BALLS)
    filler = new DiskFiller(disk).start()
    await until(async () => (await health(port)).status === 'degraded', '/api/health to say degraded')
    const pipesClosed = new Promise((resolve) => proc.child.once('close', resolve))
    proc.child.kill('SIGTERM')
    const exit = await proc.exited
    await pipesClosed
    const last = JSON.parse(proc.output().trimEnd().split('\n').at(-1))
    console.info(`[storage-fault] SIGTERM on a full disk: exit ${exit.code}, "${last.msg}"`)
    expect(exit.code).toBe(1)
    expect(last.exitCode).toBe(1)
    expect(last.dropsUnsettled).toBeGreaterThan(0)
    expect(last.msg).toMatch(new RegExp(`${last.dropsUnsettled} drops? NOT settled`))
    const [{ n }] = await backend.query(null, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'")
    expect(n).toBe(last.dropsUnsettled)
    proc = null
  }, 60_000)

  it('a process stopped on a full disk starts again on it and settles what was left', async () => {
    // The disk is still full (the filler keeps it so); the reserve was given to the last retries, so make one.
    filler.stop({ remove: false })
    fs.rmSync(filler.file, { force: true })
    fs.writeFileSync(`${file}.reserve`, Buffer.alloc(DISK_RESERVE_BYTES))
    filler = new DiskFiller(disk)
    filler.fill()
    proc = startServerProcess(`sqlite:${file}`)
    const port = await proc.port
    expect(proc.output()).toMatch(/settled drops interrupted by the last shutdown/)
    const [{ n }] = await backend.query(null, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'")
    expect(n).toBe(0)
    await expectConsistentLedger(expect, backend, null, { playerIds, startingBalance: 100000 })
    console.info(`[storage-fault] restart on a full disk: listening on ${port}, recovery settled every drop (reserve given back: ${!fs.existsSync(`${file}.reserve`)})`)
    proc.child.kill('SIGTERM')
    await proc.exited
    proc = null
  }, 60_000)
})
