import { closingLine } from '../../tools/closing-line.js'

/**
 * Ends a vitest run with one plain line, `Tests: N passed, N failed` (and
 * `, N skipped` when any were), after vitest's own coloured summary: a line a
 * CI log reader can take as the run's count whatever runner it knows.
 */
export default class ClosingLineReporter {
  onTestRunEnd (testModules, unhandledErrors) {
    const counts = { passed: 0, failed: 0, skipped: 0 }
    for (const testModule of testModules) {
      let tests = 0
      for (const test of testModule.children.allTests()) {
        tests += 1
        const state = test.result().state
        if (state === 'passed') counts.passed += 1
        else if (state === 'failed') counts.failed += 1
        else counts.skipped += 1
      }
      // A file that failed to load has no tests to count: count it as a failure.
      if (testModule.state() === 'failed' && tests === 0) counts.failed += 1
    }
    counts.failed += unhandledErrors.length
    process.stdout.write(`\n${closingLine('Tests', counts)}\n`)
  }
}
