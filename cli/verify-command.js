import { verifyDrop } from '../engine/verify-drop.js'
import { parseOptions, integerOption, rowsOption, riskOption, requiredString, engineVersionOption } from './options.js'

export const verifyUsage = 'plinko verify --server-seed S --client-seed C --nonce N [--rows 16] [--risk medium] [--engine-version V]'

/** Prints one JSON object: the commitment, the drop seed and the physics outcome under one engine version (default the newest). */
export async function verifyCommand (argv, out) {
  const options = parseOptions(argv, {
    'server-seed': { type: 'string' },
    'client-seed': { type: 'string' },
    nonce: { type: 'string' },
    rows: { type: 'string' },
    risk: { type: 'string' },
    'engine-version': { type: 'string' }
  })
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
