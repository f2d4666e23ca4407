import { parseArgs } from 'node:util'
import { UsageError } from './usage-error.js'

/**
 * node:util parseArgs with the project's own errors (UsageError, exit code 2)
 * instead of Node's, for `plinko` (cli/) and `npm run loadtest` (loadtest/):
 *
 * - an unknown option or a stray argument: `unknown option --x`, `unexpected argument "x"`;
 * - a string option without its value (`--nonce` last, or followed by another
 *   known option): `--nonce needs a value`. A value that starts with a dash
 *   but names no option (`--nonce -1`, `--server-seed -abc`) is taken as the
 *   value, and the option's own check says what is wrong with it; Node would
 *   only say the argument "is ambiguous";
 * - a boolean option given a value (`--json=yes`): `--json takes no value`;
 * - an option given twice: `--rows given twice` (unless `repeated: 'last'`,
 *   where the last one wins, or the option is `multiple: true`);
 * - a one-letter option is written `-e` only, never `--e`.
 *
 * `--help` (or `-h`, when the options declare `help`) wins over every other
 * problem: the values are then `{ help: true }` alone, so `plinko verify
 * --help` prints the usage even without the required options.
 *
 * @param {string[]} argv
 * @param {Record<string, { type: 'string' | 'boolean', short?: string, multiple?: boolean, default?: string | boolean | string[] }>} options
 * @param {{ repeated?: 'error' | 'last' }} [settings]
 * @returns {Record<string, string | boolean | string[] | undefined>}
 */
export function parseCommandLine (argv, options, { repeated = 'error' } = {}) {
  const { values, tokens } = parseArgs({ args: argv, options, strict: false, allowPositionals: true, tokens: true })
  if (options.help && tokens.some((token) => token.kind === 'option' && token.name === 'help' && token.value === undefined)) return { help: true }
  const seen = new Set()
  for (const token of tokens) {
    if (token.kind === 'option-terminator') continue
    if (token.kind === 'positional') throw new UsageError(`unexpected argument "${token.value}"`)
    const spec = Object.hasOwn(options, token.name) ? options[token.name] : undefined
    if (!spec || (token.name.length === 1 && token.rawName !== `-${token.name}`)) throw new UsageError(`unknown option ${token.rawName}`)
    const flag = token.name.length === 1 ? `-${token.name}` : `--${token.name}`
    if (spec.type === 'boolean' && token.value !== undefined) throw new UsageError(`${flag} takes no value, got "${token.value}"`)
    if (spec.type === 'string' && (token.value === undefined || (!token.inlineValue && namesAnOption(token.value, options)))) {
      throw new UsageError(`${flag} needs a value`)
    }
    if (seen.has(token.name) && !spec.multiple && repeated === 'error') throw new UsageError(`${flag} given twice: give it once`)
    seen.add(token.name)
  }
  return values
}

/** Whether an argument taken as an option's value is rather one of the options (`--rows`, `--rows=8`, `-h`). */
function namesAnOption (value, options) {
  if (value.startsWith('--')) {
    const name = value.slice(2).split('=')[0]
    return Object.hasOwn(options, name) && name.length > 1
  }
  if (/^-[A-Za-z]/.test(value)) {
    const letter = value[1]
    return Object.hasOwn(options, letter) || Object.values(options).some((spec) => spec.short === letter)
  }
  return false
}
