import { loadConfig, ConfigError } from './config.js'
import { buildApp } from './app.js'

/**
 * Starts the server: reads the configuration from the environment, builds
 * the app and listens. SIGINT/SIGTERM close it gracefully (balls in flight
 * are settled, connections closed with 1001) within SHUTDOWN_TIMEOUT_MS;
 * a second signal exits at once.
 */
let config
try {
  config = loadConfig()
} catch (error) {
  if (!(error instanceof ConfigError)) throw error
  console.error(error.message)
  process.exit(1)
}

let app
try {
  app = await buildApp(config)
  await app.listen({ port: config.port, host: config.host })
} catch (error) {
  console.error(`plinko server failed to start: ${error.message}`)
  await app?.close().catch(() => {})
  process.exit(1)
}

let closing = false
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, () => {
    if (closing) process.exit(1)
    closing = true
    app.log.info({ signal }, 'shutting down')
    // Balls in flight are settled first (arena.close); what can still hold the
    // close up is HTTP clients that never finish a request: do not wait for them.
    setTimeout(() => {
      app.log.error({ timeoutMs: config.shutdownTimeoutMs }, 'graceful shutdown timed out; exiting')
      process.exit(1)
    }, config.shutdownTimeoutMs).unref()
    app.close().then(() => process.exit(0), (error) => {
      app.log.error({ err: error }, 'shutdown failed')
      process.exit(1)
    })
  })
}
