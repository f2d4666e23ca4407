import { parseOptions } from './options.js'
import { measureDropThroughput } from './drop-throughput.js'

export const benchUsage = 'plinko bench [--quick]'

export const benchHelp = `usage: ${benchUsage}

Measures the engine: complete drops per second on one core under every
engine version (16 and 8 rows), and prints the table. The comparison with
matter-js and planck is \`npm run bench\` in a checkout.

  --quick      fewer drops
  -h, --help   this help`

/** Prints the engine's drops per second (cli/drop-throughput.js). */
export async function benchCommand (argv, out) {
  const options = parseOptions(argv, { quick: { type: 'boolean' } })
  if (options.help) {
    out.write(benchHelp + '\n')
    return
  }
  measureDropThroughput({ quick: Boolean(options.quick), log: (line) => out.write(line + '\n') })
}
