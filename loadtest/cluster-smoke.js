#!/usr/bin/env node
/**
 * `npm run loadtest:cluster-smoke [-- --vus 40 --duration 15s --workers 2]`
 *
 * The k6 players against the clustered topology: a throwaway PostgreSQL
 * (initdb/pg_ctl on PATH) and Redis, `npm run cluster -- --workers N` on a
 * free port, and `npm run loadtest` aimed at its proxy (TARGET_URL). The
 * proxy hands each WebSocket to the process with the fewest connections,
 * whatever room it asks for, so many joins reach a process that does not
 * run the room: the players must follow E_WRONG_NODE to the owner (any
 * error fails k6's thresholds). Afterwards
 * the shared ledger is checked: every drop settled, every balance equal to
 * start − bets + payouts. Exits non-zero on any failure. Loopback only;
 * bounded by the scenario's own duration.
 */
import { spawn } from 'node:child_process'
import path from 'node:path'
import { parseArgs } from 'node:util'
import { fileURLToPath } from 'node:url'
import { startPostgres } from '../tools/postgres-process.js'
import { query, ledgerMismatches, roomTotalMismatches } from '../tools/ledger-checks.js'
import { startClusterProcess } from '../tools/cluster-process.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..')
const STARTING_BALANCE = 100000
const STOP_TIMEOUT_MS = 30_000
const { values } = parseArgs({
  options: {
    vus: { type: 'string', default: '40' },
    duration: { type: 'string', default: '15s' },
    workers: { type: 'string', default: '2' },
    rooms: { type: 'string', default: '6' }
  }
})

const postgres = await startPostgres()
let cluster = null
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.once(signal, () => {
    cluster?.kill()
    postgres.stop().finally(() => process.exit(130))
  })
}
let exitCode = 1
try {
  const databaseUrl = await postgres.createDatabase()
  cluster = await startClusterProcess({ workers: Number(values.workers), env: { DATABASE_URL: databaseUrl, STARTING_BALANCE: String(STARTING_BALANCE) } })
  const k6 = spawn(process.execPath, [path.join(ROOT, 'loadtest/run.js'), '--scenario', 'players', '--vus', values.vus, '--duration', values.duration,
    '--rooms', values.rooms, '--ramp', '5s', '--env', 'BREAKDOWN=1'], { cwd: ROOT, stdio: 'inherit', env: { ...process.env, TARGET_URL: cluster.url } })
  const k6Code = await new Promise((resolve) => k6.once('exit', (code) => resolve(code ?? 1)))
  const ledger = await checkLedger(databaseUrl)
  console.log(`cluster smoke: ${ledger.drops} drops in the shared ledger, ${ledger.unsettled} unsettled, ${ledger.mismatches} balance mismatches, ${ledger.roomTotalMismatches} room totals unlike their drops; k6 exit ${k6Code}`)
  exitCode = k6Code === 0 && ledger.drops > 0 && ledger.unsettled === 0 && ledger.mismatches === 0 && ledger.roomTotalMismatches === 0 ? 0 : 1
} catch (error) {
  console.error(`cluster smoke: ${error.stack ?? error.message}`)
} finally {
  if (cluster && !await cluster.stop(STOP_TIMEOUT_MS)) console.error(`cluster smoke: the cluster did not stop within ${STOP_TIMEOUT_MS} ms; killed it`)
  await postgres.stop()
}
process.exit(exitCode)

async function checkLedger (url) {
  const [counts] = await query(url, "SELECT count(*) AS drops, count(*) FILTER (WHERE status <> 'settled') AS unsettled FROM drops")
  const mismatches = await ledgerMismatches(url, STARTING_BALANCE)
  const roomTotals = await roomTotalMismatches(url)
  return { drops: Number(counts.drops), unsettled: Number(counts.unsettled), mismatches: mismatches.length, roomTotalMismatches: roomTotals.length }
}
