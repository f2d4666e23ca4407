import { readFileSync } from 'node:fs'
import os from 'node:os'
import { ENGINE_VERSION } from '../engine/index.js'

const { version: SERVER_VERSION } = JSON.parse(readFileSync(new URL('../package.json', import.meta.url), 'utf8'))

/**
 * The URLs the server answers on, the first the one to open: one per
 * address it listens on (fastify's `app.addresses()`); a wildcard address
 * (HOST=0.0.0.0 or ::) stands for http://localhost:PORT and then every
 * external address of this machine's interfaces (as fastify logs them).
 * @param {{ address: string, family: string | number, port: number }[]} addresses
 * @param {ReturnType<typeof os.networkInterfaces>} [interfaces]
 * @returns {string[]}
 */
export function listenUrls (addresses, interfaces = os.networkInterfaces()) {
  const urls = []
  for (const { address, family, port } of addresses) {
    const ipv6 = family === 'IPv6' || family === 6
    if (address !== '0.0.0.0' && address !== '::') {
      urls.push(`http://${ipv6 ? `[${address}]` : address}:${port}`)
      continue
    }
    urls.push(`http://localhost:${port}`)
    for (const entry of Object.values(interfaces).flat()) {
      // 0.0.0.0 is IPv4 only; :: takes both.
      if (!entry || entry.internal || (entry.family === 'IPv6' && !ipv6) || entry.address.startsWith('fe80:')) continue
      urls.push(`http://${entry.family === 'IPv6' ? `[${entry.address}]` : entry.address}:${port}`)
    }
  }
  return [...new Set(urls)]
}

/** A connection URL with its password (if any) replaced by `***`. @param {string} url */
export function hidePassword (url) {
  try {
    const parsed = new URL(url)
    if (parsed.password) parsed.password = '***'
    return parsed.toString()
  } catch {
    return '(unparsable URL, hidden)'
  }
}

/**
 * The few lines printed on a terminal once the server listens (server.js;
 * only for a person: see log-format.js `outputMode`): where to play, where
 * the ledger is, whether this process runs alone or clustered, where the
 * operator token comes from (printed when it was generated for this run),
 * the log format and how to stop. Plain text, no colours; the logs follow.
 * @param {import('./config.js').Config} config
 * @param {{ urls: string[], logs: 'pretty' | 'json', node?: string }} where urls from listenUrls(), the first shown as the one to open
 * @returns {string}
 */
export function startBanner (config, { urls, logs, node = process.version }) {
  const [main = '(not listening)', ...others] = urls
  const rows = [
    ['play', `${main}/`],
    ...others.map((url) => ['also', `${url}/`]),
    ['audit', `${main}/audit (operators)   API: ${main}/docs`],
    ['ledger', ledgerLine(config.database)],
    ['runs', config.redisUrl
      ? `clustered: rooms leased through Redis ${hidePassword(config.redisUrl)}; this process is ${config.publicUrl || main}`
      : 'one process alone: every room, nonce and drop id here'],
    ['operator', config.operatorTokenGenerated
      ? `OPERATOR_TOKEN was not set; generated for this run: ${config.operatorToken}\n            (set OPERATOR_TOKEN, 32 random bytes in hex, to keep one across restarts)`
      : 'OPERATOR_TOKEN from the environment (not shown)'],
    ['logs', logs === 'pretty' ? 'pretty, below (LOG_FORMAT=json for JSON lines)' : 'JSON lines, below (pretty ones need the dev dependency pino-pretty)'],
    ['stop', 'Ctrl-C: plays every ball in flight to its end, settles it, closes the sockets, exits']
  ]
  const title = `Plinko Arena ${SERVER_VERSION} (engine ${ENGINE_VERSION}, Node ${node})`
  return [title, ...rows.map(([label, text]) => `  ${label.padEnd(10)}${text}`)].join('\n') + '\n\n'
}

/** @param {import('./config.js').Config['database']} database */
function ledgerLine (database) {
  if (database.kind === 'postgres') return `PostgreSQL ${hidePassword(database.url)}`
  if (database.file === ':memory:') return 'SQLite in memory (gone when the process exits)'
  return `SQLite ${database.file}`
}
