import { describe, it, expect, afterEach } from 'vitest'
import WebSocket from 'ws'
import { clusterTestbed, eventually } from './helpers/cluster.js'

/**
 * Issue #21, item 7, the WebSocket side: sockets, drops and joins per
 * address were counted per process, so two workers let an address hold
 * twice WS_MAX_CONNECTIONS_PER_IP and drop at twice DROP_RATE_PER_IP. Each
 * process now enforces 1/N of each budget, N the processes alive
 * (server/limits/worker-share.js, a heartbeat in Redis).
 */
describe('cluster: the per-address WebSocket budgets are the cluster\'s', () => {
  const testbed = clusterTestbed()
  const sockets = []
  // Each test's processes go with it: they count as workers on the one Redis while they run.
  afterEach(async () => {
    for (const socket of sockets.splice(0)) socket.terminate()
    await testbed.closeAll()
    for (const node of testbed.nodes.splice(0)) await node.stop()
  })

  async function twoNodes (env) {
    const databaseUrl = await testbed.postgres.createDatabase()
    const nodes = [await testbed.startNode({ databaseUrl, env }), await testbed.startNode({ databaseUrl, env })]
    // Both have seen each other's heartbeat.
    for (const node of nodes) {
      await eventually(async () => /plinko_ws_address_limit_workers 2\b/.test(await (await fetch(`${node.url}/metrics`)).text()))
    }
    return nodes
  }

  /** Opens a socket (kept open) and resolves with its first message: welcome, or the error that refused it. */
  function firstMessage (url) {
    const socket = new WebSocket(url)
    sockets.push(socket)
    return new Promise((resolve, reject) => {
      socket.once('message', (data) => resolve(JSON.parse(data.toString())))
      socket.once('error', reject)
    })
  }

  it('lets one address hold 4 sockets in all with WS_MAX_CONNECTIONS_PER_IP=4 over two processes (2 each), and drop 2 balls in all with DROP_RATE_PER_IP=1 (burst 2)', async () => {
    const nodes = await twoNodes({ WS_MAX_CONNECTIONS_PER_IP: '4', DROP_RATE_PER_IP: '1' })
    const session = await nodes[0].session()
    const outcomes = []
    for (const node of nodes) {
      for (let i = 0; i < 3; i++) outcomes.push(await firstMessage(node.wsUrl(session.token)))
    }
    const welcomed = outcomes.filter((m) => m.type === 'welcome')
    const refused = outcomes.filter((m) => m.code === 'E_TOO_MANY_CONNECTIONS')
    expect({ welcomed: welcomed.length, refused: refused.length }).toEqual({ welcomed: 4, refused: 2 })
    for (const socket of sockets.splice(0)) socket.terminate()

    // One socket on each, each in a room its process owns; 5 drops on each, sent at once.
    const onA = await testbed.connect(nodes[0], session.token)
    const onB = await testbed.connect(nodes[1], session.token)
    expect((await testbed.join(onA, '8-low')).type).toBe('joined')
    expect((await testbed.join(onB, '9-high')).type).toBe('joined')
    for (let i = 0; i < 5; i++) {
      onA.send({ type: 'drop', bet: 1, ref: `a${i}` })
      onB.send({ type: 'drop', bet: 1, ref: `b${i}` })
    }
    const replies = []
    for (let i = 0; i < 5; i++) {
      replies.push(await onA.take((m) => m.ref === `a${i}`), await onB.take((m) => m.ref === `b${i}`))
    }
    const dropped = replies.filter((m) => m.type === 'dropped')
    // 2 s of refill at 0.5 a second per process would be needed for a third: the 10 replies come within milliseconds.
    expect(dropped).toHaveLength(2)
    expect(replies.filter((m) => m.code === 'E_RATE_LIMITED')).toHaveLength(8)
  })

  it('gives the whole budget back to the process left once the other stops', async () => {
    const nodes = await twoNodes({ WS_MAX_CONNECTIONS_PER_IP: '4' })
    const session = await nodes[0].session()
    expect((await nodes[1].stop()).code).toBe(0)
    await eventually(async () => /plinko_ws_address_limit_workers 1\b/.test(await (await fetch(`${nodes[0].url}/metrics`)).text()))
    const outcomes = []
    for (let i = 0; i < 5; i++) outcomes.push(await firstMessage(nodes[0].wsUrl(session.token)))
    expect(outcomes.map((m) => m.type === 'welcome' ? 'welcome' : m.code)).toEqual(['welcome', 'welcome', 'welcome', 'welcome', 'E_TOO_MANY_CONNECTIONS'])
  })
})
