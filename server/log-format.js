import { createRequire } from 'node:module'
import pino from 'pino'

/** LOG_FORMAT: `auto` (pretty on a terminal, JSON otherwise), `json`, `pretty`. */
export const LOG_FORMATS = Object.freeze(['auto', 'json', 'pretty'])

/**
 * How the server speaks to whoever reads its output: for a person at a
 * terminal, the start-up banner (server/start-banner.js) and pretty logs;
 * for a machine (stdout piped or redirected, a container's log collector),
 * JSON lines only. pino-pretty is a development dependency: where it is not
 * installed (`npm ci --omit=dev`, the Docker image) a terminal still gets
 * the banner, its logs stay JSON, quietly under `auto`; `notice` says why
 * when LOG_FORMAT=pretty asked for them.
 * @param {{ isTTY: boolean, logFormat: 'auto' | 'json' | 'pretty', prettyAvailable: boolean }} where
 * @returns {{ logs: 'pretty' | 'json', banner: boolean, notice?: string }}
 */
export function outputMode ({ isTTY, logFormat, prettyAvailable }) {
  const human = logFormat === 'pretty' || (logFormat === 'auto' && isTTY === true)
  if (!human) return { logs: 'json', banner: false }
  if (prettyAvailable) return { logs: 'pretty', banner: true }
  if (logFormat === 'pretty') return { logs: 'json', banner: true, notice: 'LOG_FORMAT=pretty, but pino-pretty (a development dependency) is not installed: logging JSON lines' }
  return { logs: 'json', banner: true }
}

/** Where pino-pretty is installed, or null (a production install). @returns {string | null} */
export function prettyTarget () {
  try {
    return createRequire(import.meta.url).resolve('pino-pretty')
  } catch {
    return null
  }
}

/**
 * Where the logs go, as fastify logger options: for `logs: 'pretty'`,
 * pino-pretty on a worker thread (a pino transport, flushed when the
 * process exits); for JSON lines, stdout written synchronously. pino's
 * default stdout stream writes asynchronously and its exit hook skips a
 * write still in progress, so a line logged just before process.exit (the
 * shut-down report) could be lost.
 * @param {'pretty' | 'json'} logs @param {{ target?: string | null, colorize?: boolean }} [options]
 * @returns {{ transport: object } | { stream: import('pino').DestinationStream }}
 */
export function logOutput (logs, { target = prettyTarget(), colorize = false } = {}) {
  if (logs === 'pretty' && target) return { transport: { target, options: { colorize, translateTime: 'SYS:HH:MM:ss.l', ignore: 'pid,hostname', singleLine: true } } }
  return { stream: pino.destination({ dest: 1, sync: true }) }
}
