/**
 * players.js: VUS players spread over ROOMS rooms, each connecting during
 * RAMP, dropping one ball every DROP_INTERVAL for DURATION, then waiting for
 * its last settles and leaving. Fails (k6 exit 99) on any error, balance
 * mismatch or unsettled drop, or when latency or jitter pass their limits.
 *
 *   k6 run -e BASE_URL=http://127.0.0.1:8080 -e VUS=50 -e DURATION=20s -e ROOMS=5 loadtest/players.js
 *
 * Settings: see k6-lib/scenario-config.js. Usually run through `npm run loadtest`.
 */
import { readScenarioConfig, playerScenarioOptions } from './k6-lib/scenario-config.js'
import { chooseRooms, playScheduledPlayer } from './k6-lib/player.js'

const config = readScenarioConfig({ duration: '60s', ramp: '10s' })

export const options = playerScenarioOptions(config, 'players')

export function setup () {
  return { rooms: chooseRooms(config.baseUrl, config.rooms) }
}

export default function ({ rooms }) {
  playScheduledPlayer(config, rooms)
}
