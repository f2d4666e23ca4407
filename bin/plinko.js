#!/usr/bin/env node
import { UsageError } from '../cli/usage-error.js'
import { verifyCommand, verifyUsage } from '../cli/verify-command.js'
import { rtpCommand, rtpUsage } from '../cli/rtp-command.js'
import { benchCommand, benchUsage } from '../cli/bench-command.js'

const commands = { verify: verifyCommand, rtp: rtpCommand, bench: benchCommand }
const usage = `usage:
  ${verifyUsage}
  ${rtpUsage}
  ${benchUsage}`

const [name, ...rest] = process.argv.slice(2)
if (name === 'help' || name === '--help' || name === '-h') {
  process.stdout.write(usage + '\n')
  process.exit(0)
}
if (name === undefined) {
  process.stderr.write(`plinko: a command is required\n${usage}\n`)
  process.exit(2)
}
const command = commands[name]
try {
  if (!command) throw new UsageError(`unknown command "${name}"`)
  await command(rest, process.stdout, process.stderr)
} catch (error) {
  if (error instanceof UsageError || error instanceof RangeError || error instanceof TypeError) {
    process.stderr.write(`plinko: ${error.message}\n${usage}\n`)
    process.exit(2)
  }
  process.stderr.write(`plinko: ${error.stack ?? error}\n`)
  process.exit(1)
}
