import { loadConfig, ConfigError } from './config.js'
import { buildApp } from './app.js'
import { logOutput, outputMode, prettyTarget } from './log-format.js'
import { listenUrls, startBanner } from './start-banner.js'
import { acceptHandedOffSockets } from './cluster/socket-handoff.js'

/**
 * Starts the server: reads the configuration from the environment, builds
 * the app and listens. On a terminal it prints a start-up banner and pretty
 * logs; otherwise (or with LOG_FORMAT=json) JSON lines only (log-format.js).
 * SIGINT/SIGTERM close it gracefully (balls in flight are settled,
 * connections closed with 1001) within SHUTDOWN_TIMEOUT_MS, and its last
 * log line says how that went and with which exit code; a second signal
 * exits at once.
 */
let config
try {
  config = loadConfig()
} catch (error) {
  if (!(error instanceof ConfigError)) throw error
  console.error(error.message)
  process.exit(1)
}

// Signals are taken from the start: one that comes while the server is still
// starting (a supervisor's SIGTERM right after "listening") shuts it down
// gracefully once it has started, instead of killing it half-way.
let stopSignal = null
let started = false
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, () => {
    // A second signal exits at once.
    if (stopSignal !== null) process.exit(1)
    stopSignal = signal
    if (started) shutDown(signal)
  })
}

const isTTY = process.stdout.isTTY === true
const output = outputMode({ isTTY, logFormat: config.logFormat, prettyAvailable: prettyTarget() !== null })

let app
try {
  app = await buildApp(config, { logOutput: logOutput(output.logs, { colorize: isTTY }), announceToken: !output.banner })
  if (output.notice) app.log.warn(output.notice)
  await app.listen({ port: config.port, host: config.host })
} catch (error) {
  console.error(`plinko server failed to start: ${error.message}`)
  await app?.close().catch(() => {})
  process.exit(1)
}
if (output.banner) process.stdout.write(startBanner(config, { urls: listenUrls(app.addresses()), logs: output.logs }))
// Under npm run cluster, the proxy hands WebSockets over instead of piping them.
acceptHandedOffSockets(app.server)
started = true
if (stopSignal !== null) shutDown(stopSignal)

/** @param {number} n @param {string} noun */
function count (n, noun) {
  return `${n} ${noun}${n === 1 ? '' : 's'}`
}

/**
 * The graceful stop: balls in flight settled, connections closed with 1001,
 * then one last line with what was settled and closed and the exit code
 * (1 whenever a drop is left unsettled: its payout could not be written).
 * @param {string} signal
 */
function shutDown (signal) {
  const stopping = Date.now()
  const before = { balls: app.arena.unsettledDrops, sockets: app.websocketServer.clients.size }
  app.log.info({ signal, dropsInFlight: before.balls, sockets: before.sockets }, 'shutting down')
  /** The last line: what was settled and closed, and the exit code; then exit. */
  const finish = (exitCode, outcome, extra = {}) => {
    const left = { balls: app.arena.unsettledDrops, sockets: app.websocketServer.clients.size }
    // A drop left unsettled (the ledger would not take its payout) is a failed stop, whatever else went well.
    if (left.balls > 0) exitCode = Math.max(exitCode, 1)
    const report = {
      signal,
      exitCode,
      dropsSettled: before.balls - left.balls,
      dropsUnsettled: left.balls,
      socketsClosed: Math.max(0, before.sockets - left.sockets),
      socketsOpen: left.sockets,
      durationMs: Date.now() - stopping,
      ...extra
    }
    const summary = `${count(report.dropsSettled, 'drop')} in flight settled, ${count(report.socketsClosed, 'socket')} closed` +
      (left.balls > 0 ? `, ${count(left.balls, 'drop')} NOT settled (start-up recovery settles them)` : '') +
      (left.sockets > 0 ? `, ${count(left.sockets, 'socket')} still open` : '')
    app.log[exitCode === 0 ? 'info' : 'error'](report, `${outcome}: ${summary}; exit code ${exitCode}`)
    process.exit(exitCode)
  }
  // Balls in flight are settled first (arena.close); what can still hold the
  // close up is HTTP clients that never finish a request: do not wait for them.
  setTimeout(() => {
    finish(1, `graceful shutdown timed out after ${config.shutdownTimeoutMs} ms`, { timeoutMs: config.shutdownTimeoutMs })
  }, config.shutdownTimeoutMs).unref()
  app.close().then(() => finish(0, 'shut down'), (error) => finish(1, 'shutdown failed', { err: error }))
}
