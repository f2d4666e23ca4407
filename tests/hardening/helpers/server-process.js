import { startServerProcess as launchServerProcess } from '../../../tools/server-process.js'
import { OPERATOR_TOKEN } from '../../server/helpers/server.js'
import { LIFTED_LIMITS } from '../../../tools/lifted-limits.js'

/**
 * The server as a child process (scripts/server-process.js) with the test
 * operator token and limits lifted for tests.
 * @param {string} databaseUrl @param {Record<string, string>} [env]
 */
export function startServerProcess (databaseUrl, env = {}) {
  return launchServerProcess(databaseUrl, {
    OPERATOR_TOKEN,
    CLIENT_DIR: '/nonexistent/plinko-client',
    ...LIFTED_LIMITS,
    ...env
  })
}
