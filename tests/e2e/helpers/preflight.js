import { preflight } from '../../preflight.js'

/** globalSetup of `npm run test:e2e` (vitest.e2e.config.js): see tests/preflight.js. */
export default function () {
  preflight('e2e')
}
