import fs from 'node:fs'
import path from 'node:path'

/**
 * vitest globalSetup of `npm test` and `npm run test:e2e`: before any test
 * file runs, checks that the system programs the tests start for real are
 * there, and otherwise stops the run with one message that names the
 * missing ones and the command that installs them (instead of hundreds of
 * failures, each about a server that did not start).
 *
 * PostgreSQL's initdb and pg_ctl are looked for on PATH, then where Debian
 * and Ubuntu put them (/usr/lib/postgresql/<version>/bin, not on PATH);
 * a directory found there is put on PATH for the tests.
 */

/** What each run needs: a program, and the Debian package that has it. */
export const NEEDS = {
  // python3 with venv: the engine's second implementation (verifier-python/, tests/spec/).
  test: [['initdb', 'postgresql'], ['pg_ctl', 'postgresql'], ['redis-server', 'redis-server'], ['nginx', 'nginx'], ['python3', 'python3-venv']],
  e2e: [['initdb', 'postgresql'], ['pg_ctl', 'postgresql'], ['redis-server', 'redis-server'], ['chromium', 'chromium']]
}

/** The full path of `program` in one of the directories of `PATH`, or null. */
export function onPath (program, PATH = '') {
  for (const dir of PATH.split(path.delimiter)) {
    if (!dir) continue
    const file = path.join(dir, program)
    try {
      fs.accessSync(file, fs.constants.X_OK)
      return file
    } catch {}
  }
  return null
}

/** The newest <postgresRoot>/<version>/bin holding initdb and pg_ctl, or null. */
function debianPostgresBin (postgresRoot) {
  let versions
  try {
    versions = fs.readdirSync(postgresRoot).filter((v) => /^\d+$/.test(v)).sort((a, b) => Number(b) - Number(a))
  } catch {
    return null
  }
  const bins = versions.map((version) => path.join(postgresRoot, version, 'bin'))
  return bins.find((bin) => onPath('initdb', bin) && onPath('pg_ctl', bin)) ?? null
}

/**
 * What `run` lacks, as the one message to print, or null when nothing is
 * missing. Puts Debian's PostgreSQL bin directory on env.PATH when that is
 * where initdb and pg_ctl are. Chromium is CHROMIUM_PATH or /usr/bin/chromium
 * and redis-server may be named by REDIS_SERVER, as the tests that start them allow.
 * @param {'test' | 'e2e'} run
 * @param {NodeJS.ProcessEnv} [env]
 * @param {{ postgresRoot?: string }} [places] where Debian's PostgreSQL versions are
 */
export function missingPrograms (run, env = process.env, { postgresRoot = '/usr/lib/postgresql' } = {}) {
  if (!(onPath('initdb', env.PATH) && onPath('pg_ctl', env.PATH))) {
    const bin = debianPostgresBin(postgresRoot)
    if (bin) env.PATH = [bin, env.PATH].filter(Boolean).join(path.delimiter)
  }
  const found = (program) => {
    if (program === 'chromium') return fs.existsSync(env.CHROMIUM_PATH || '/usr/bin/chromium') // as tests/e2e/helpers/browser.js launches it
    if (program === 'redis-server' && env.REDIS_SERVER) return fs.existsSync(env.REDIS_SERVER)
    return onPath(program, env.PATH) !== null
  }
  const missing = NEEDS[run].filter(([program]) => !found(program))
  if (missing.length === 0) return null
  const packages = [...new Set(missing.map(([, pkg]) => pkg))]
  const sudo = process.getuid?.() === 0 ? '' : 'sudo '
  return `${run === 'e2e' ? 'npm run test:e2e' : 'npm test'} needs ${missing.map(([program]) => program).join(', ')} ` +
    '(the tests start real ones), not found. Install them with:\n\n' +
    `  ${sudo}apt-get install -y ${packages.join(' ')}\n\n` +
    '(Debian, Ubuntu; elsewhere, the same programs from your system\'s packages: see docs/tests.md.)'
}

/** Stops the run, before any test file, when `run` lacks a program. @param {'test' | 'e2e'} run */
export function preflight (run) {
  const message = missingPrograms(run)
  if (!message) return
  console.error(`\n${message}\n`)
  process.exit(1)
}

/** globalSetup of `npm test` (vitest.config.js). */
export default function () {
  preflight('test')
}
