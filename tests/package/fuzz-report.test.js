import { describe, it, expect, beforeAll, afterAll } from 'vitest'
import { spawnSync } from 'node:child_process'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { fuzzCounts, reshapeLine } from '../../scripts/fuzz-report.js'

/**
 * scripts/fuzz-report.js: the fuzzer's output passes through, its
 * pytest-shaped closing banner loses its rules, and the run ends with the
 * plain `Fuzz: N passed, N failed` line and the fuzzer's exit status.
 */
const ROOT = fileURLToPath(new URL('../../', import.meta.url))
const PASSING = [
  'Test cases:',
  '  1692 generated, 1692 passed, 18 skipped',
  '',
  'Seed: 244620578',
  '',
  '============================= 2 warnings in 15.00s ============================='
]
const FAILING = [
  'Test cases:',
  '  400 generated, 7 found 2 unique failures, 3 errored, 5 skipped',
  '',
  '=========================== 2 failures, 3 errors in 9.10s ==========================='
]
let dir

beforeAll(() => { dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-fuzz-report-')) })
afterAll(() => { fs.rmSync(dir, { recursive: true, force: true }) })

/** Runs the report around a stand-in fuzzer that prints `lines` and exits with `status`. */
function run (lines, status) {
  const fake = path.join(dir, `fuzzer-${status}.js`)
  fs.writeFileSync(fake, `process.stdout.write(${JSON.stringify(lines.join('\n') + '\n')}); process.stderr.write('a warning\\n'); process.exit(${status})\n`)
  return spawnSync(process.execPath, [path.join(ROOT, 'scripts/fuzz-report.js'), '--', process.execPath, fake], { encoding: 'utf8' })
}

describe('the fuzzer\'s closing line', () => {
  it('passes the output through and ends it with the counts of a passing run', () => {
    const result = run(PASSING, 0)
    expect(result.status).toBe(0)
    const lines = result.stdout.trimEnd().split('\n')
    expect(lines.at(-1)).toBe('Fuzz: 1692 passed, 0 failed, 18 skipped')
    expect(lines.at(-2)).toBe('Schemathesis: 2 warnings in 15.00s')
    expect(lines.slice(0, 4)).toEqual(PASSING.slice(0, 4))
    expect(result.stderr).toBe('a warning\n')
  })

  // 400 generated − 7 with failures − 3 errored − 5 skipped = 385 passed.
  it('counts unique failures and errors, and keeps the fuzzer\'s exit status', () => {
    const result = run(FAILING, 1)
    expect(result.status).toBe(1)
    expect(result.stdout.trimEnd().split('\n').at(-1)).toBe('Fuzz: 385 passed, 5 failed, 5 skipped')
  })

  it('counts a failed run without a summary as one failure, and a command that cannot start as failed', () => {
    expect(fuzzCounts(['Traceback (most recent call last):'], 2)).toEqual({ passed: 0, failed: 1, skipped: 0 })
    const missing = spawnSync(process.execPath, [path.join(ROOT, 'scripts/fuzz-report.js'), '--', path.join(dir, 'no-such-fuzzer')], { encoding: 'utf8' })
    expect(missing.status).toBe(127)
    expect(missing.stdout.trimEnd().split('\n').at(-1)).toBe('Fuzz: 0 passed, 1 failed')
  })

  it('unframes only a closing banner', () => {
    expect(reshapeLine('=================================== SUMMARY ====================================')).toContain('SUMMARY')
    expect(reshapeLine('=================================== SUMMARY ====================================')).toMatch(/^=+ SUMMARY =+$/)
    expect(reshapeLine('==== No issues found in 180.00s ====')).toBe('Schemathesis: No issues found in 180.00s')
    expect(reshapeLine('==== Interrupted after 3.20s ====')).toBe('Schemathesis: Interrupted after 3.20s')
  })
})
