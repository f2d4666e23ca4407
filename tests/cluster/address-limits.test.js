import { describe, it, expect } from 'vitest'
import { clusterTestbed, OPERATOR_TOKEN } from './helpers/cluster.js'

/**
 * Issue #21, item 7: per-address limits were per process, so 2 workers let
 * 40 of 40 sessions through a limit of 30 a minute. In a cluster they are
 * counted in Redis (server/limits/address-limits.js): the cluster's limit is
 * the configured one. And item 8: a join while Redis is down got E_INTERNAL.
 */
describe('cluster: per-address limits are the cluster\'s, and a Redis outage', () => {
  const testbed = clusterTestbed()

  async function twoNodes (env) {
    const databaseUrl = await testbed.postgres.createDatabase()
    return [await testbed.startNode({ databaseUrl, env }), await testbed.startNode({ databaseUrl, env })]
  }

  it('lets 30 of 40 sessions through a SESSION_RATE_LIMIT of 30 spread over two processes, and 10 of 20 wrong operator tokens through AUTH_FAILURE_LIMIT=10', async () => {
    const nodes = await twoNodes({ SESSION_RATE_LIMIT: '30', AUTH_FAILURE_LIMIT: '10' })
    const sessions = []
    for (let i = 0; i < 40; i++) sessions.push((await nodes[i % 2].api('POST', '/api/session')).status)
    expect(sessions.filter((s) => s === 201)).toHaveLength(30)
    expect(sessions.filter((s) => s === 429)).toHaveLength(10)

    const guesses = []
    for (let i = 0; i < 20; i++) {
      const response = await fetch(`${nodes[i % 2].url}/api/audit/drops`, { headers: { authorization: `Bearer wrong-token-${i}` } })
      guesses.push(response.status)
    }
    expect(guesses.slice(0, 10)).toEqual(Array(10).fill(403))
    expect(guesses.slice(10)).toEqual(Array(10).fill(429))
    // The right token from the blocked address waits too, on either process.
    for (const node of nodes) {
      const response = await fetch(`${node.url}/api/audit/drops`, { headers: { authorization: `Bearer ${OPERATOR_TOKEN}` } })
      expect(response.status).toBe(429)
      expect(Number(response.headers.get('retry-after'))).toBeGreaterThan(0)
    }
  })

  it('answers a join during a Redis outage with E_ROOM_MOVING (and retryAfterMs), not E_INTERNAL', async () => {
    const [node] = await twoNodes({})
    const session = await node.session()
    const client = await testbed.connect(node, session.token)
    expect((await testbed.join(client, '8-low')).type).toBe('joined')
    await testbed.redis.stop()
    const reply = await testbed.join(client, '9-high')
    expect(reply).toMatchObject({ type: 'error', code: 'E_ROOM_MOVING', room: '9-high', retryAfterMs: expect.any(Number) })
    expect(reply.retryAfterMs).toBeGreaterThan(0)
    expect(node.output).not.toMatch(/"level":50.*message handler failed/)
  })
})
