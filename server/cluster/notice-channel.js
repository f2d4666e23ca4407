/**
 * A process's subscription to cluster notices on Redis (balance changes,
 * seed rotations): a connection of its own, since a subscribed connection
 * can do nothing else, and JSON objects only. Anything else published on
 * the channels (not JSON, or JSON that is no object) is ignored, never
 * thrown into the connection's event handler.
 */

/**
 * @param {object} options
 * @param {import('ioredis').Redis} options.redis the process's connection, duplicated for the subscription
 * @param {string[]} options.channels
 * @param {string} options.what the notices, for the log ('balance notices')
 * @param {import('pino').Logger} options.log
 * @param {(channel: string, notice: Record<string, any>) => void} options.onNotice
 * @returns {Promise<import('ioredis').Redis>} the subscribed connection: close it with closeNotices()
 */
export async function subscribeToNotices ({ redis, channels, what, log, onNotice }) {
  const subscriber = redis.duplicate()
  subscriber.on('error', (error) => log.warn({ err: error }, `redis (${what}) error`))
  subscriber.on('message', (channel, text) => {
    const notice = parseNotice(text)
    if (notice) onNotice(channel, notice)
  })
  await subscriber.subscribe(...channels)
  return subscriber
}

/** @param {import('ioredis').Redis | null} subscriber */
export async function closeNotices (subscriber) {
  await subscriber?.quit().catch(() => subscriber.disconnect())
}

/** A notice as published: a JSON object, or null. @param {string} text */
export function parseNotice (text) {
  try {
    const value = JSON.parse(text)
    return value && typeof value === 'object' ? value : null
  } catch {
    return null
  }
}
