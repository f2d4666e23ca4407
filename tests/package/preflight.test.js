import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { spawnSync } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { missingPrograms } from '../preflight.js'

/**
 * `npm test` on a machine that lacks the system programs the tests start
 * (tests/preflight.js, vitest's globalSetup): one message naming what is
 * missing and the command that installs it, before any test file runs.
 */
const ROOT = fileURLToPath(new URL('../../', import.meta.url))
let dir

beforeAll(() => { dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-preflight-')) })
afterAll(() => { fs.rmSync(dir, { recursive: true, force: true }) })

/** A directory holding an executable stub of each program. */
function stubs (name, programs) {
  const bin = path.join(dir, name)
  fs.mkdirSync(bin, { recursive: true })
  for (const program of programs) fs.writeFileSync(path.join(bin, program), '#!/bin/sh\n', { mode: 0o755 })
  return bin
}

describe('the preflight of npm test', () => {
  const nowhere = { postgresRoot: '/nonexistent/postgresql' }

  it('names every missing program and the one command that installs them', () => {
    const message = missingPrograms('test', { PATH: stubs('empty', []) }, nowhere)
    expect(message).toMatch(/^npm test needs initdb, pg_ctl, redis-server, nginx, python3 /)
    expect(message).toMatch(/apt-get install -y postgresql redis-server nginx python3-venv\n/)
  })

  it('names only what is missing; e2e needs Chromium instead of nginx', () => {
    const env = { PATH: stubs('some', ['initdb', 'pg_ctl', 'nginx', 'python3']), CHROMIUM_PATH: path.join(dir, 'no-chromium') }
    expect(missingPrograms('test', { ...env }, nowhere)).toMatch(/^npm test needs redis-server \(/)
    expect(missingPrograms('e2e', { ...env }, nowhere)).toMatch(/^npm run test:e2e needs redis-server, chromium .*\n\n {2}\S*apt-get install -y redis-server chromium\n/s)
  })

  it('is silent when everything is there', () => {
    expect(missingPrograms('test', { PATH: stubs('all', ['initdb', 'pg_ctl', 'redis-server', 'nginx', 'python3']) }, nowhere)).toBeNull()
  })

  it('finds PostgreSQL where Debian puts it (off PATH) and puts it on PATH for the tests', () => {
    const postgresRoot = path.join(dir, 'postgresql')
    const bin = stubs('postgresql/15/bin', ['initdb', 'pg_ctl'])
    const env = { PATH: stubs('rest', ['redis-server', 'nginx', 'python3']) }
    expect(missingPrograms('test', env, { postgresRoot })).toBeNull()
    expect(env.PATH.split(path.delimiter)[0]).toBe(bin)
  })

  it('stops a real `vitest run` before any test file, with that one message, on a PATH with only Node', () => {
    const started = performance.now()
    const run = spawnSync(process.execPath, [path.join(ROOT, 'node_modules/vitest/vitest.mjs'), 'run', 'tests/package/runtime-and-install.test.js'], {
      cwd: ROOT,
      env: { PATH: path.dirname(process.execPath), HOME: os.homedir() },
      encoding: 'utf8',
      timeout: 30_000
    })
    const output = run.stdout + run.stderr
    console.info(`[preflight] a vitest run with only Node on PATH stopped after ${(performance.now() - started).toFixed(0)} ms (exit ${run.status})`)
    expect(run.status).toBe(1)
    expect(output).toMatch(/npm test needs (initdb, pg_ctl, )?redis-server, nginx, python3 \(/)
    expect(output.match(/ needs /g)).toHaveLength(1)
    expect(output).not.toMatch(/runtime-and-install|Test Files/)
  })
})
