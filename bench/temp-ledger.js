import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { loadConfig } from '../server/config.js'

/**
 * The server benchmarks' shared set-up: a temporary folder for a fresh
 * SQLite ledger, removed when the run ends (also on Ctrl-C), and the
 * server configuration over it — silent, a rich starting balance, the
 * benchmark's own settings on top.
 *
 *   await withBenchLedger({ DROP_RATE: '1000' }, async (config, dir) => { … })
 *
 * @param {Record<string, string>} env configuration beyond the shared one
 * @param {(config: import('../server/config.js').Config, dir: string) => Promise<void>} run
 */
export async function withBenchLedger (env, run) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-bench-'))
  const remove = () => fs.rmSync(dir, { recursive: true, force: true })
  const onSignal = () => { remove(); process.exit(130) }
  for (const signal of ['SIGINT', 'SIGTERM']) process.once(signal, onSignal)
  try {
    const config = loadConfig({
      DATABASE_URL: `sqlite:${path.join(dir, 'ledger.sqlite')}`,
      OPERATOR_TOKEN: 'bench-operator-token-0123456789',
      LOG_LEVEL: 'silent',
      STARTING_BALANCE: '1000000000',
      CLIENT_DIR: path.join(dir, 'no-client'),
      ...env
    })
    await run(config, dir)
  } finally {
    for (const signal of ['SIGINT', 'SIGTERM']) process.removeListener(signal, onSignal)
    remove()
  }
}
