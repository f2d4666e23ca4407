/** A bad command line: printed with the usage hint, exit code 2. */
export class UsageError extends Error {
  constructor (message) {
    super(message)
    this.name = 'UsageError'
  }
}

/**
 * A script's options from its command line: `parse(argv)` (throwing
 * UsageError on bad input); on a UsageError the message and the usage go
 * to stderr and the process exits 2; with --help (`options.help`) the usage
 * goes to stdout and it exits 0.
 * @template T @param {(argv: string[]) => T & { help?: boolean }} parse
 * @param {string[]} argv @param {string} usage @returns {T}
 */
export function optionsOrExit (parse, argv, usage) {
  let options
  try {
    options = parse(argv)
  } catch (error) {
    if (!(error instanceof UsageError)) throw error
    console.error(`${error.message}\n\n${usage}`)
    process.exit(2)
  }
  if (options.help) {
    console.log(usage)
    process.exit(0)
  }
  return options
}
