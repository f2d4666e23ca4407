import { startServerProcess as launchServerProcess } from '../../../scripts/server-process.js'
import { OPERATOR_TOKEN } from '../../server/helpers/server.js'

/**
 * The server as a child process (scripts/server-process.js) with the test
 * operator token and limits lifted for tests.
 * @param {string} databaseUrl @param {Record<string, string>} [env]
 */
export function startServerProcess (databaseUrl, env = {}) {
  return launchServerProcess(databaseUrl, {
    OPERATOR_TOKEN,
    CLIENT_DIR: '/nonexistent/plinko-client',
    HTTP_RATE_LIMIT: '1000000',
    SESSION_RATE_LIMIT: '1000000',
    DROP_RATE_PER_IP: '1000000',
    JOIN_RATE_PER_IP: '1000000',
    ...env
  })
}
