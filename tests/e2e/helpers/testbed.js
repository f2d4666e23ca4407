import { beforeAll, afterAll } from 'vitest'
import { startArenaServer } from './arena-server.js'
import { launchChromium } from './browser.js'
import { GameClient } from '../../server/helpers/game-client.js'

/**
 * The real server and Debian's Chromium for one e2e test file: started
 * before its tests, closed after them (the browser first). `use` gets
 * `{ server, chromium }` once both run (and may set up more: it is
 * awaited before the tests start), e.g.
 * `serverAndChromium({ tickRate: 60 }, (started) => ({ server, chromium } = started))`.
 * @param {Parameters<typeof startArenaServer>[0]} serverOptions
 * @param {(started: { server: any, chromium: any }) => void | Promise<void>} use
 */
export function serverAndChromium (serverOptions, use) {
  const started = { server: null, chromium: null }
  beforeAll(async () => {
    started.server = await startArenaServer(serverOptions)
    started.chromium = await launchChromium()
    await use(started)
  })
  afterAll(async () => {
    await started.chromium?.close()
    await started.server?.close()
  })
}

/**
 * A fresh guest player who drops `drops` balls of `bet` in `room` over the
 * protocol and waits for each to settle: the history an operator-page test
 * looks at. Returns the session and the player's drops as /api/drops lists them.
 * @param {any} server @param {{ room: string, drops: number, bet: number }} play
 */
export async function playerWithSettledDrops (server, { room, drops, bet }) {
  const player = (await server.api('POST', '/api/session')).body
  const client = await GameClient.connect(server.wsUrl(player.token))
  client.send({ type: 'join', room })
  await client.take('joined')
  for (let i = 0; i < drops; i++) client.send({ type: 'drop', bet })
  for (let i = 0; i < drops; i++) await client.take('settled', 60_000)
  await client.close()
  return { player, drops: (await server.api('GET', '/api/drops', { token: player.token })).body.drops }
}
