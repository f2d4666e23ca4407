/**
 * The player page in a cluster (issue #7): two server processes with a real
 * Redis and PostgreSQL behind the small proxy of `npm run cluster`, each
 * process's PUBLIC_URL being its /n/{i} path on the proxy (nginx does the
 * same in Docker). The page is loaded from process 0; its room runs on
 * process 1, so the join is answered E_WRONG_NODE. The page must follow it
 * by itself: reconnect to the owner, join, drop and verify as usual, with
 * the same session and balance, and its drops in the one shared ledger.
 */
import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { startPostgres } from '../../tools/postgres-process.js'
import { GameClient } from '../server/helpers/game-client.js'
import { startRedis, startNode, freePort, query, ledgerMismatches } from '../cluster/helpers/cluster.js'
import { createProxy } from '../../server/cluster/proxy.js'
import { launchChromium, waitInPage } from './helpers/browser.js'

const CLIENT_DIR = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../client')
const ROOM = '12-high'

let postgres, redis, proxy, chromium, owner
const nodes = []

beforeAll(async () => {
  postgres = await startPostgres()
  redis = await startRedis()
  const databaseUrl = await postgres.createDatabase()
  const proxyPort = await freePort()
  for (let i = 0; i < 2; i++) {
    nodes.push(await startNode({
      databaseUrl,
      redisUrl: redis.url,
      env: { CLIENT_DIR, PUBLIC_URL: `http://127.0.0.1:${proxyPort}/n/${i}`, WS_MAX_CONNECTIONS_PER_IP: '1000' }
    }))
  }
  proxy = createProxy({ targets: nodes.map((node) => ({ host: '127.0.0.1', port: node.port })), log: { warn () {} } })
  await new Promise((resolve) => proxy.listen(proxyPort, '127.0.0.1', resolve))
  proxy.base = `http://127.0.0.1:${proxyPort}`
  proxy.databaseUrl = databaseUrl
  chromium = await launchChromium()
  // Process 1 runs the room: someone joined it there first.
  const session = await nodes[1].session()
  owner = await GameClient.connect(nodes[1].wsUrl(session.token))
  owner.send({ type: 'join', room: ROOM })
  await owner.take('joined')
}, 120_000)

afterAll(async () => {
  await chromium?.close()
  await owner?.close().catch(() => {})
  await new Promise((resolve) => proxy ? proxy.close(resolve) : resolve())
  for (const node of nodes) await node.stop().catch(() => {})
  await redis?.stop()
  await postgres?.stop()
})

describe('player page in a cluster', () => {
  it('follows E_WRONG_NODE to the process that runs its room, then plays and verifies there', async () => {
    const page = await chromium.newPage()
    const [rows, risk] = ROOM.split('-')
    // The page remembers its room; start it on ROOM straight away.
    await page.addInitScript((room) => localStorage.setItem('plinko.room', room), ROOM)
    await page.goto(`${proxy.base}/n/0/`)
    await waitInPage(page, `the page to join ${ROOM} on process 1`, (room) => window.__plinko?.room === room, ROOM)
    expect(await page.evaluate(() => window.__plinko.socketBase)).toBe(`${proxy.base}/n/1`)
    expect(await page.evaluate(() => window.__plinko.connects)).toBe(2) // process 0, then process 1
    expect(await page.inputValue('#rows')).toBe(rows)
    expect(await page.inputValue('#risk')).toBe(risk)

    const before = await page.evaluate(() => window.__plinko.balance)
    for (let i = 0; i < 3; i++) await page.click('#drop')
    await waitInPage(page, '3 verified drops', () => window.__plinko.verifications.length >= 3 && window.__plinko.pendingVerifications === 0)
    const verifications = await page.evaluate(() => window.__plinko.verifications)
    expect(verifications.every((v) => v.verified)).toBe(true)

    // The drops are in the shared ledger, run by process 1, and the balance adds up.
    const playerId = await page.evaluate(() => window.__plinko.playerId)
    const drops = await query(proxy.databaseUrl, "SELECT bet, payout FROM drops WHERE player_id = $1 AND status = 'settled'", [playerId])
    expect(drops).toHaveLength(3)
    // The ledger holds payouts in milli-credits, the page shows credits.
    const expected = (Math.round(before * 1000) - drops.reduce((sum, d) => sum + Number(d.bet) * 1000 - Number(d.payout), 0)) / 1000
    await waitInPage(page, 'the settled balance', (balance) => window.__plinko.balance === balance, expected)
    expect(await ledgerMismatches(proxy.databaseUrl, 100000)).toEqual([])
    expect(page.problems).toEqual([])
  })
})
