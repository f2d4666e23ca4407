/**
 * Runs the fuzzer (the command after `--`), passes its output through line
 * by line, and ends it with the plain closing line CI's log reader counts:
 * `Fuzz: N passed, N failed[, N skipped]`, from Schemathesis's "Test cases"
 * summary and the run's exit status. Exits with the fuzzer's status.
 *
 * Why: Schemathesis closes with a pytest-shaped banner ("=== 2 warnings in
 * 180.00s ==="), which a reader of pytest's closing lines takes for a pytest
 * run that executed no test. The banner keeps its words, without the rules.
 */
import { spawn } from 'node:child_process'
import readline from 'node:readline'
import { fileURLToPath } from 'node:url'
import { closingLine } from '../tools/closing-line.js'

const BANNER = /^=+ (.+ (?:in|after) \d+(?:\.\d+)?s) =+$/

/** The line as printed, with Schemathesis's closing banner unframed. */
export function reshapeLine (line) {
  const banner = BANNER.exec(line)
  return banner ? `Schemathesis: ${banner[1]}` : line
}

/**
 * The run's counts from its "Test cases:" summary line ("1692 generated,
 * 1692 passed, 18 skipped" or "1692 generated, 5 found 2 unique failures,
 * 3 errored"), and its exit status: a run that failed counts at least one
 * failure, one that printed no summary did not finish.
 * @param {string[]} lines
 * @param {number} status
 */
export function fuzzCounts (lines, status) {
  const at = lines.findIndex((line) => line.trim() === 'Test cases:')
  const summary = at >= 0 ? (lines[at + 1] ?? '') : ''
  const number = (pattern) => Number(pattern.exec(summary)?.[1] ?? 0)
  const generated = number(/(\d+) generated/)
  const withFailures = number(/(\d+) found \d+ unique failures?/)
  const errored = number(/(\d+) errored/)
  const skipped = number(/(\d+) skipped/)
  const passed = /\d+ passed/.test(summary) ? number(/(\d+) passed/) : Math.max(0, generated - withFailures - errored - skipped)
  let failed = number(/found (\d+) unique failures?/) + errored
  if (status !== 0 && failed === 0) failed = 1
  return { passed, failed, skipped }
}

async function main () {
  const separator = process.argv.indexOf('--')
  const [command, ...args] = process.argv.slice(separator + 1)
  if (separator < 0 || !command) throw new Error('usage: node scripts/fuzz-report.js -- <fuzzer> [args…]')
  const child = spawn(command, args, { stdio: ['ignore', 'pipe', 'pipe'] })
  const lines = []
  const pass = (stream, out) => new Promise((resolve) => {
    const reader = readline.createInterface({ input: stream, crlfDelay: Infinity })
    reader.on('line', (line) => { lines.push(line); out.write(reshapeLine(line) + '\n') })
    reader.on('close', resolve)
  })
  const exited = new Promise((resolve) => {
    child.on('error', (error) => { process.stderr.write(`${command}: ${error.message}\n`); resolve(127) })
    child.on('close', (code, signal) => resolve(code ?? (signal ? 128 : 1)))
  })
  const [status] = await Promise.all([exited, pass(child.stdout, process.stdout), pass(child.stderr, process.stderr)])
  process.stdout.write(`${closingLine('Fuzz', fuzzCounts(lines, status))}\n`)
  process.exitCode = status
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) await main()
