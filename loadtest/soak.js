/**
 * soak.js: a steady load for a long time (DURATION, default 10 min; RAMP
 * 30 s). Same checks and thresholds as players.js; run it through
 * `npm run loadtest -- --scenario soak` so the report shows whether memory
 * and tick duration stay flat.
 *
 *   k6 run -e VUS=1000 -e DURATION=10m loadtest/soak.js
 */
import { readScenarioConfig, playerScenarioOptions } from './k6-lib/scenario-config.js'
import { chooseRooms, playScheduledPlayer } from './k6-lib/player.js'

const config = readScenarioConfig({ duration: '10m', ramp: '30s', vus: 500 })

export const options = playerScenarioOptions(config, 'soak')

export function setup () {
  return { rooms: chooseRooms(config.baseUrl, config.rooms) }
}

export default function ({ rooms }) {
  playScheduledPlayer(config, rooms)
}
