#!/usr/bin/env node
import { UsageError } from '../cli/usage-error.js'
import { verifyCommand, verifyUsage, verifyHelp } from '../cli/verify-command.js'
import { rtpCommand, rtpUsage, rtpHelp } from '../cli/rtp-command.js'
import { benchCommand, benchUsage, benchHelp } from '../cli/bench-command.js'

// `plinko COMMAND [options]`: `plinko COMMAND --help` (or `plinko help
// COMMAND`) prints that command's usage and options, exit 0. A bad command
// line prints the reason and the command's usage, exit 2; a failure, exit 1.
const commands = {
  verify: { run: verifyCommand, usage: verifyUsage, help: verifyHelp },
  rtp: { run: rtpCommand, usage: rtpUsage, help: rtpHelp },
  bench: { run: benchCommand, usage: benchUsage, help: benchHelp }
}
const usage = `usage:
${Object.values(commands).map((command) => `  ${command.usage}`).join('\n')}
  plinko help [COMMAND]

plinko COMMAND --help shows a command's options.`

const [name, ...rest] = process.argv.slice(2)
if (name === 'help' || name === '--help' || name === '-h') {
  const topic = rest[0]
  if (topic === undefined) {
    process.stdout.write(usage + '\n')
    process.exit(0)
  }
  if (!Object.hasOwn(commands, topic) || rest.length > 1) {
    process.stderr.write(`plinko: ${rest.length > 1 ? `help takes one command, got ${rest.length}` : `unknown command "${topic}"`}\n${usage}\n`)
    process.exit(2)
  }
  process.stdout.write(commands[topic].help + '\n')
  process.exit(0)
}
if (name === undefined) {
  process.stderr.write(`plinko: a command is required\n${usage}\n`)
  process.exit(2)
}
if (!Object.hasOwn(commands, name)) {
  process.stderr.write(`plinko: unknown command "${name}"\n${usage}\n`)
  process.exit(2)
}
const command = commands[name]
try {
  await command.run(rest, process.stdout, process.stderr)
} catch (error) {
  if (error instanceof UsageError || error instanceof RangeError || error instanceof TypeError) {
    process.stderr.write(`plinko ${name}: ${error.message}\nusage: ${command.usage}\n(plinko ${name} --help lists the options)\n`)
    process.exit(2)
  }
  process.stderr.write(`plinko ${name}: ${error.stack ?? error}\n`)
  process.exit(1)
}
