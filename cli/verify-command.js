import { verifyDrop } from '../engine/verify-drop.js'
import { parseOptions, integerOption, rowsOption, riskOption, requiredString, engineVersionOption, SEED_AND_BOARD_OPTIONS, BOARD_OPTIONS_HELP } from './options.js'

export const verifyUsage = 'plinko verify --server-seed S --client-seed C --nonce N [--rows 16] [--risk medium] [--engine-version V]'

export const verifyHelp = `usage: ${verifyUsage}

Replays one drop from its seeds and prints one JSON object:
{ serverSeedHash, dropSeed, bucket, multiplier, ticks, stateHash, engineVersion }

  --server-seed S      the revealed server seed (required)
  --client-seed C      the drop's client seed (required; may be empty)
  --nonce N            the drop's nonce: a whole number, 0 or more (required)
${BOARD_OPTIONS_HELP}: the drop's engineVersion
  -h, --help           this help`

const OPTIONS = { ...SEED_AND_BOARD_OPTIONS, nonce: { type: 'string' } }

/** Prints one JSON object: the commitment, the drop seed and the physics outcome under one engine version (default the newest). */
export async function verifyCommand (argv, out) {
  const options = parseOptions(argv, OPTIONS)
  if (options.help) {
    out.write(verifyHelp + '\n')
    return
  }
  const result = await verifyDrop({
    serverSeed: requiredString(options['server-seed'], 'server-seed'),
    clientSeed: options['client-seed'] ?? requiredString(undefined, 'client-seed'),
    nonce: integerOption(options.nonce, 'nonce'),
    rows: rowsOption(options.rows),
    risk: riskOption(options.risk),
    engineVersion: engineVersionOption(options['engine-version'])
  })
  out.write(JSON.stringify(result) + '\n')
}
