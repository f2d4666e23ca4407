import { parseOptions } from './options.js'

export const benchUsage = 'plinko bench [--quick]'

/** Runs the engine benchmarks (ours against matter-js and planck) and prints the tables. */
export async function benchCommand (argv, out) {
  const options = parseOptions(argv, { quick: { type: 'boolean' } })
  let runEngineBenchmarks
  try {
    ({ runEngineBenchmarks } = await import('../bench/engine-bench.js'))
  } catch (error) {
    throw new Error(`the benchmarks need the development dependencies (npm install): ${error.message}`)
  }
  await runEngineBenchmarks({ quick: Boolean(options.quick), log: (line) => out.write(line + '\n') })
}
