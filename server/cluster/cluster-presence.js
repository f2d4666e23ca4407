import os from 'node:os'
import { randomBytes } from 'node:crypto'
import Redis from 'ioredis'

/**
 * This process in the cluster: its node id and its one Redis connection,
 * shared by room ownership and the account feed (each subscriber is a
 * duplicate of it). Connected by whichever part starts first, closed after
 * both have left.
 */
export class ClusterPresence {
  /** @param {{ config: { redisUrl: string }, log: import('pino').Logger }} options */
  constructor ({ config, log }) {
    this.nodeId = `${os.hostname()}-${process.pid}-${randomBytes(3).toString('hex')}`
    this.redis = new Redis(config.redisUrl, { lazyConnect: true, maxRetriesPerRequest: 2, enableOfflineQueue: true })
    this.redis.on('error', (error) => log.warn({ err: error }, 'redis error'))
    this._connecting = null
  }

  /** Connects once (later calls share the first attempt). */
  connect () {
    this._connecting ??= this.redis.connect()
    return this._connecting
  }

  async close () {
    if (!this._connecting) return this.redis.disconnect()
    await this.redis.quit().catch(() => this.redis.disconnect())
  }
}
