import { parseOptions } from './options.js'

export const benchUsage = 'plinko bench [--quick]'

export const benchHelp = `usage: ${benchUsage}

Runs the engine benchmarks (this engine against matter-js and planck; needs
the development dependencies) and prints the tables.

  --quick      fewer and shorter runs
  -h, --help   this help`

/** Runs the engine benchmarks (ours against matter-js and planck) and prints the tables. */
export async function benchCommand (argv, out) {
  const options = parseOptions(argv, { quick: { type: 'boolean' } })
  if (options.help) {
    out.write(benchHelp + '\n')
    return
  }
  let runEngineBenchmarks
  try {
    ({ runEngineBenchmarks } = await import('../bench/engine-bench.js'))
  } catch (error) {
    throw new Error(`the benchmarks need the development dependencies (npm install): ${error.message}`)
  }
  await runEngineBenchmarks({ quick: Boolean(options.quick), log: (line) => out.write(line + '\n') })
}
