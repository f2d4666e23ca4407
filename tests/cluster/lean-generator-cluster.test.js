import { describe, it, expect } from 'vitest'
import { clusterTestbed, ledgerMismatches, roomTotalMismatches } from './helpers/cluster.js'
import { runLeanLoad } from '../../loadtest/lean/lean-generator.js'

/**
 * The lean load generator against two clustered processes (real PostgreSQL
 * and Redis): every player enters through process A; those whose room runs
 * on B are answered E_WRONG_NODE, follow it to B and play there, with every
 * check as strict as on one process (balances, every drop settled, 0 errors).
 */
const START = 100000

describe('cluster: the lean generator follows E_WRONG_NODE', () => {
  const testbed = clusterTestbed()

  it('plays the players of a room on another process there, every check passing', async () => {
    const { connect, join } = testbed
    const databaseUrl = await testbed.postgres.createDatabase()
    const [a, b] = [await testbed.startNode({ databaseUrl, env: { STARTING_BALANCE: String(START) } }), await testbed.startNode({ databaseUrl, env: { STARTING_BALANCE: String(START) } })]
    // B takes the first room the generator will use; A takes the second when its players join.
    const { roomIds } = await (await fetch(`${a.url}/api/rooms`)).json()
    const holder = await connect(b, (await b.session()).token)
    expect(await join(holder, roomIds[0])).toMatchObject({ type: 'joined' })

    const summary = await runLeanLoad({ baseUrl: a.url, players: 8, rooms: 2, durationS: 3, rampS: 1, dropIntervalMs: 400, drainS: 15 })
    expect(summary.failures).toEqual([])
    expect(summary.passed).toBe(true)
    // Players 0, 2, 4, 6 are in the room B runs: each followed one redirect.
    expect(summary.redirects).toBe(4)
    expect(summary.joined).toBe(8)
    expect(summary.dropsSent).toBeGreaterThan(16)
    expect(summary.dropsSettled).toBe(summary.dropsSent)

    // B still runs the room its holder is in (the generator's players there have left).
    const { rooms } = await (await fetch(`${a.url}/api/rooms`)).json()
    expect(rooms.find((r) => r.id === roomIds[0]).owner).toBe(b.url)
    expect(await ledgerMismatches(databaseUrl, START)).toEqual([])
    expect(await roomTotalMismatches(databaseUrl)).toEqual([])
  })
})
