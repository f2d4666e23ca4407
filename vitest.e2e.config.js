import { defineConfig } from 'vitest/config'

/**
 * End-to-end tests: the real server and the browser client in Debian's
 * headless Chromium (playwright-core). `npm run test:e2e`. Files run one
 * at a time: each drives a browser and a 60 Hz server, and CI machines are small.
 */
export default defineConfig({
  test: {
    include: ['tests/e2e/**/*.test.js'],
    // Stops at once, with one message, if Chromium, PostgreSQL or Redis is missing.
    globalSetup: ['tests/e2e/helpers/preflight.js'],
    testTimeout: 240_000,
    hookTimeout: 360_000,
    // vitest's summary, then one plain `Tests: N passed, N failed` line.
    reporters: ['default', './tests/reporters/closing-line.js'],
    pool: 'forks',
    fileParallelism: false
  }
})
