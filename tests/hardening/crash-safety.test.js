import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { STORE_KINDS, storeBackend } from '../server/helpers/stores.js'
import { GameClient } from '../server/helpers/game-client.js'
import { startServerProcess } from './helpers/server-process.js'
import { expectConsistentLedger } from './helpers/ledger.js'

/**
 * Crash safety, end to end: players drop hundreds of balls on a real server
 * process, which is killed with SIGKILL while drops are in flight (and more
 * are arriving). After a restart on the same database every drop the server
 * acknowledged (`dropped`) is in the ledger exactly once, settled from its
 * seed with its payout, and every balance is start + payouts − bets.
 */
const PLAYERS = 6
const ROOMS = ['16-high', '16-medium', '15-low', '14-high', '16-low', '13-medium']
const ACKED_BEFORE_KILL = 1200
const START = 100000
const ENV = { DROP_RATE: '100', DROP_BURST: '100', MAX_BALLS_PER_ROOM: '4096' }

describe.each(STORE_KINDS)('crash safety on %s', (kind) => {
  const backend = storeBackend(kind)
  beforeAll(async () => { await backend.setup() })
  afterAll(async () => { await backend.teardown() })

  it(`loses no acknowledged drop when killed with SIGKILL mid-flight (${ACKED_BEFORE_KILL}+ drops)`, async () => {
    const db = await backend.newDatabase()
    const proc = startServerProcess(db.url, ENV)
    const players = []
    let stopSending = false
    try {
      const port = await proc.port
      for (let i = 0; i < PLAYERS; i++) {
        const session = await (await fetch(`http://127.0.0.1:${port}/api/session`, { method: 'POST' })).json()
        const client = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
        client.send({ type: 'join', room: ROOMS[i] })
        await client.take('joined')
        players.push({ session, client })
      }
      // Every player drops a ball every 30 ms with a varying bet, until the kill.
      const senders = players.map(({ client }, p) => (async () => {
        for (let n = 0; !stopSending; n++) {
          if (client.socket.readyState === 1) client.send({ type: 'drop', bet: 1 + ((n * 7 + p * 13) % 50) })
          await new Promise((resolve) => setTimeout(resolve, 30))
        }
      })())
      const acked = () => players.reduce((sum, { client }) => sum + client.messages.filter((m) => m.type === 'dropped' && m.player === client.welcome.playerId).length, 0)
      while (acked() < ACKED_BEFORE_KILL) await new Promise((resolve) => setTimeout(resolve, 10))
      proc.child.kill('SIGKILL')
      await proc.exited
      stopSending = true
      await Promise.all(senders)
      await Promise.all(players.map(({ client }) => client.closed))
    } finally {
      stopSending = true
      proc.child.kill('SIGKILL')
    }

    const ackedDrops = players.flatMap(({ client, session }) => client.messages
      .filter((m) => m.type === 'dropped' && m.player === session.playerId)
      .map((m) => ({ ...m, settledBeforeCrash: client.messages.find((s) => s.type === 'settled' && s.dropId === m.dropId) })))
    expect(ackedDrops.length).toBeGreaterThanOrEqual(ACKED_BEFORE_KILL)
    // The crash left drops in flight (otherwise this test proves little).
    const [inFlight] = await backend.query(db.database, "SELECT COUNT(*) AS n FROM drops WHERE status = 'in_flight'")
    expect(Number(inFlight.n)).toBeGreaterThan(0)
    const settledBeforeCrash = ackedDrops.filter((d) => d.settledBeforeCrash).length

    const restarted = startServerProcess(db.url, ENV)
    try {
      const port = await restarted.port
      expect(restarted.output()).toMatch(/settled drops interrupted by the last shutdown/)
      const ledger = await expectConsistentLedger(expect, backend, db.database, { playerIds: players.map((p) => p.session.playerId), startingBalance: START })
      for (const drop of ackedDrops) {
        const row = ledger.get(drop.dropId)
        expect(row, `acknowledged drop ${drop.dropId} is in the ledger`).toBeDefined()
        expect(row).toMatchObject({ playerId: drop.player, bet: drop.bet })
        if (drop.settledBeforeCrash) expect(row.payout).toBe(Math.round(drop.settledBeforeCrash.payout * 1000)) // milli-credits in the ledger
      }
      // Each player sees the recovered balance on reconnect.
      for (const { session } of players) {
        const [row] = await backend.query(db.database, 'SELECT balance FROM players WHERE id = $1', [session.playerId])
        const client = await GameClient.connect(`ws://127.0.0.1:${port}/ws?token=${session.token}`)
        expect(Math.round(client.welcome.balance * 1000)).toBe(Number(row.balance)) // the ledger holds milli-credits
        await client.close()
      }
      console.info(`[crash-safety ${kind}] acknowledged ${ackedDrops.length} drops, ledger ${ledger.size}, in flight at the kill ${Number(inFlight.n)}, settled before it ${settledBeforeCrash}; all settled after restart, balances exact`)
    } finally {
      restarted.child.kill('SIGTERM')
      await restarted.exited
    }
  })
})
