import { defineConfig } from 'vitest/config'
import { fileURLToPath } from 'node:url'

// The pages import the shared folders by the URLs the server serves them at
// (/engine/…, /protocol/…, /charts/…); in Node tests those are the folders.
const shared = ['engine', 'protocol', 'charts'].map((dir) => ({
  find: new RegExp(`^/${dir}/`),
  replacement: fileURLToPath(new URL(`./${dir}/`, import.meta.url))
}))

export default defineConfig({
  resolve: { alias: shared },
  test: {
    include: ['tests/**/*.test.js'],
    exclude: ['tests/e2e/**', 'node_modules/**'],
    // Stops at once, with one message, if PostgreSQL, Redis or nginx is missing.
    globalSetup: ['tests/preflight.js'],
    testTimeout: 60_000,
    hookTimeout: 120_000,
    // vitest's summary, then one plain `Tests: N passed, N failed` line.
    reporters: ['default', './tests/reporters/closing-line.js'],
    pool: 'forks'
  }
})
