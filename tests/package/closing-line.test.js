import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { spawnSync } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { fileURLToPath } from 'node:url'

/**
 * The last line of a vitest run (tests/reporters/closing-line.js): the plain
 * `Tests: N passed, N failed[, N skipped]` count, after vitest's own summary.
 */
const ROOT = fileURLToPath(new URL('../../', import.meta.url))
const REPORTER = path.join(ROOT, 'tests/reporters/closing-line.js')
let dir

beforeAll(() => {
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-closing-line-'))
  fs.writeFileSync(path.join(dir, 'vitest.config.js'), 'export default { test: { include: ["*.check.js"] } }\n')
  fs.writeFileSync(path.join(dir, 'mixed.check.js'), [
    "import { it, expect } from 'vitest'",
    "it('passes', () => expect(1 + 1).toBe(2))",
    "it('passes too', () => expect('a').toBe('a'))",
    "it('fails', () => expect(1).toBe(2))",
    "it.skip('is skipped', () => {})"
  ].join('\n'))
})
afterAll(() => { fs.rmSync(dir, { recursive: true, force: true }) })

function lastLine (files) {
  const run = spawnSync(process.execPath, [path.join(ROOT, 'node_modules/vitest/vitest.mjs'), 'run', ...files, '--reporter=default', `--reporter=${REPORTER}`], {
    cwd: dir, env: { ...process.env, NO_COLOR: '1' }, encoding: 'utf8'
  })
  const lines = run.stdout.trimEnd().split('\n')
  return { line: lines[lines.length - 1], status: run.status }
}

describe('the closing line of a vitest run', () => {
  it('counts what passed, failed and was skipped, as the last line, alone on it', () => {
    const { line, status } = lastLine(['mixed.check.js'])
    expect(status).toBe(1)
    expect(line).toBe('Tests: 2 passed, 1 failed, 1 skipped')
  })

  it('counts a file that cannot load as a failure', () => {
    fs.writeFileSync(path.join(dir, 'broken.check.js'), "import './no-such-module.js'\n")
    const { line, status } = lastLine(['broken.check.js'])
    expect(status).toBe(1)
    expect(line).toBe('Tests: 0 passed, 1 failed')
  })
})
