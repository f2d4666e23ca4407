import { describe, it, expect } from 'vitest'
import { parseCommandLine } from '../../cli/command-line.js'
import { UsageError } from '../../cli/usage-error.js'

const OPTIONS = {
  help: { type: 'boolean', short: 'h' },
  nonce: { type: 'string' },
  rows: { type: 'string' },
  'server-seed': { type: 'string' },
  json: { type: 'boolean' },
  e: { type: 'string', multiple: true }
}

function problem (argv, settings) {
  try {
    parseCommandLine(argv, OPTIONS, settings)
  } catch (error) {
    expect(error).toBeInstanceOf(UsageError)
    return error.message
  }
  throw new Error(`${argv.join(' ')} was accepted`)
}

describe('the command-line parser (node:util parseArgs with the project\'s errors)', () => {
  it('reads separate and inline values, booleans and repeatable options', () => {
    expect(parseCommandLine(['--nonce', '7', '--rows=9', '--json', '-e', 'A=1', '-eB=2'], OPTIONS)).toEqual({ nonce: '7', rows: '9', json: true, e: ['A=1', 'B=2'] })
    expect(parseCommandLine([], OPTIONS)).toEqual({})
  })

  it('takes a dash-led value that names no option as the value, for the option\'s own check to judge', () => {
    expect(parseCommandLine(['--nonce', '-1'], OPTIONS)).toEqual({ nonce: '-1' })
    expect(parseCommandLine(['--server-seed', '-abc', '--nonce', '--x'], OPTIONS)).toEqual({ 'server-seed': '-abc', nonce: '--x' })
  })

  it('says which option lacks its value, rather than Node\'s "argument is ambiguous"', () => {
    expect(problem(['--nonce'])).toBe('--nonce needs a value')
    expect(problem(['--server-seed', '--nonce', '3'])).toBe('--server-seed needs a value')
    expect(problem(['--server-seed', '--rows=8'])).toBe('--server-seed needs a value')
    expect(problem(['--nonce', '-h'])).toBe('--nonce needs a value')
    expect(problem(['-e'])).toBe('-e needs a value')
  })

  it('refuses a repeated option, unless told the last one wins', () => {
    expect(problem(['--rows', '8', '--rows', '9'])).toBe('--rows given twice: give it once')
    expect(problem(['--json', '--json'])).toBe('--json given twice: give it once')
    expect(parseCommandLine(['--rows', '8', '--rows=9'], OPTIONS, { repeated: 'last' })).toEqual({ rows: '9' })
  })

  it('refuses unknown options, stray arguments, values for booleans and --e for -e', () => {
    expect(problem(['--frobnicate'])).toBe('unknown option --frobnicate')
    expect(problem(['-x'])).toBe('unknown option -x')
    expect(problem(['--e', 'A=1'])).toBe('unknown option --e')
    expect(problem(['--constructor'])).toBe('unknown option --constructor')
    expect(problem(['verify'])).toBe('unexpected argument "verify"')
    expect(problem(['--', '--rows'])).toBe('unexpected argument "--rows"')
    expect(problem(['--json=yes'])).toBe('--json takes no value, got "yes"')
  })

  it('lets --help win over every other problem', () => {
    expect(parseCommandLine(['--rows', '8', '--rows', '9', '--frobnicate', '--help'], OPTIONS)).toEqual({ help: true })
    expect(parseCommandLine(['-h'], OPTIONS)).toEqual({ help: true })
    // Only when the command declares it, and not as another option's value.
    expect(() => parseCommandLine(['--help'], { rows: { type: 'string' } })).toThrow('unknown option --help')
    expect(parseCommandLine(['--server-seed=--help'], OPTIONS)).toEqual({ 'server-seed': '--help' })
  })
})
