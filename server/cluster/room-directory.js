import { ROOM_IDS } from '../../protocol/room-id.js'
import { Leases } from './lease.js'

/**
 * Which process runs which room, in Redis (used by cluster-room-ownership.js;
 * a server that runs alone has no directory: every room is its own).
 *
 *   claim(roomId)   → { held: true } | { held: false, owner: url | null, retryAfterMs }
 *   renew(roomIds)  → room ids whose lease was lost to another process
 *   release(roomId) → gives the room up (only if we still hold it)
 *   publish(list)   → advertises this process and its rooms' summaries
 *   list()          → every room running anywhere: its summary plus `owner` (a URL)
 *
 * Redis keys (all under `plinko:`):
 *   room:{id}:lease   owner node id, PX = lease TTL (lease.js)
 *   room:{id}:summary JSON summary as GET /api/rooms shows it, PX = lease TTL
 *   node:{nodeId}     the node's public URL, PX = lease TTL (presence)
 */
export const KEYS = {
  lease: (roomId) => `plinko:room:${roomId}:lease`,
  summary: (roomId) => `plinko:room:${roomId}:summary`,
  node: (nodeId) => `plinko:node:${nodeId}`
}

export class RedisRoomDirectory {
  /**
   * @param {object} options
   * @param {import('ioredis').Redis} options.redis
   * @param {string} options.nodeId unique per process
   * @param {() => string} options.publicUrl how clients reach this process
   * @param {number} options.ttlMs
   * @param {() => object[]} options.localSummaries rooms this process runs now
   */
  constructor ({ redis, nodeId, publicUrl, ttlMs, localSummaries }) {
    this.redis = redis
    this.nodeId = nodeId
    this.publicUrl = publicUrl
    this.ttlMs = ttlMs
    this.localSummaries = localSummaries
    this.leases = new Leases({ redis, owner: nodeId, ttlMs })
  }

  async claim (roomId) {
    if (await this.leases.take(KEYS.lease(roomId))) return { held: true }
    const [owner, ttl] = await this.redis.multi().get(KEYS.lease(roomId)).pttl(KEYS.lease(roomId)).exec().then((r) => r.map(([, v]) => v))
    const url = owner === null ? null : await this.redis.get(KEYS.node(owner))
    return { held: false, owner: url, retryAfterMs: Math.max(50, Number(ttl) > 0 ? Number(ttl) : 50) }
  }

  async renew (roomIds) {
    const lost = await this.leases.renew(roomIds.map(KEYS.lease))
    return lost.map((key) => key.slice('plinko:room:'.length, -':lease'.length))
  }

  async release (roomId) {
    const released = await this.leases.release(KEYS.lease(roomId))
    if (released) await this.redis.del(KEYS.summary(roomId))
    return released
  }

  /** Presence and summaries, renewed together with the leases. @param {object[]} summaries */
  async publish (summaries) {
    const multi = this.redis.multi().set(KEYS.node(this.nodeId), this.publicUrl(), 'PX', this.ttlMs)
    for (const summary of summaries) multi.set(KEYS.summary(summary.id), JSON.stringify(summary), 'PX', this.ttlMs)
    await multi.exec()
  }

  async list () {
    const leaseKeys = ROOM_IDS.map(KEYS.lease)
    const summaryKeys = ROOM_IDS.map(KEYS.summary)
    const values = await this.redis.mget(...leaseKeys, ...summaryKeys)
    const owners = values.slice(0, ROOM_IDS.length)
    const summaries = values.slice(ROOM_IDS.length)
    const nodes = [...new Set(owners.filter((o) => o !== null))]
    const urls = new Map()
    if (nodes.length > 0) {
      const found = await this.redis.mget(...nodes.map(KEYS.node))
      nodes.forEach((node, i) => urls.set(node, found[i]))
    }
    const local = new Map(this.localSummaries().map((s) => [s.id, s]))
    const rooms = []
    ROOM_IDS.forEach((id, i) => {
      const owner = owners[i]
      if (owner === null) return
      const summary = owner === this.nodeId && local.has(id) ? local.get(id) : parseSummary(summaries[i], id)
      rooms.push({ ...summary, owner: urls.get(owner) ?? null })
    })
    return rooms
  }

}

function parseSummary (text, id) {
  const [rows, risk] = [Number(id.slice(0, id.indexOf('-'))), id.slice(id.indexOf('-') + 1)]
  const empty = { id, rows, risk, players: 0, ballsInFlight: 0, tick: 0 }
  if (text === null) return empty
  try { return { ...empty, ...JSON.parse(text) } } catch { return empty }
}
