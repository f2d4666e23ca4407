/**
 * spike.js: VUS players connect within RAMP (default 5 s: a spike), play
 * for DURATION (default 20 s), then leave spread over LEAVE (default 5 s).
 * Same checks and thresholds as players.js.
 *
 *   k6 run -e VUS=2000 -e RAMP=5s -e DURATION=20s loadtest/spike.js
 */
import { readScenarioConfig, playerScenarioOptions } from './k6-lib/scenario-config.js'
import { chooseRooms, playScheduledPlayer } from './k6-lib/player.js'

const config = readScenarioConfig({ duration: '20s', ramp: '5s', leave: '5s' })

export const options = playerScenarioOptions(config, 'spike')

export function setup () {
  return { rooms: chooseRooms(config.baseUrl, config.rooms) }
}

export default function ({ rooms }) {
  playScheduledPlayer(config, rooms)
}
