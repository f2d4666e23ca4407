import { describe, it, expect } from 'vitest'
import { HeartbeatSchedule } from '../../server/realtime/heartbeat-schedule.js'

/** A connection that records the ticks it was pinged at. */
function peer (clock) {
  return { pings: [], heartbeat () { this.pings.push(clock.tick) } }
}

/** Runs ticks [from, to) of the schedule, the clock showing each. */
function run (schedule, clock, from, to) {
  for (let tick = from; tick < to; tick++) {
    clock.tick = tick
    schedule.tick(tick)
  }
}

describe('heartbeat schedule: each connection pinged once per period, the pings spread over its ticks', () => {
  it('pings every connection exactly once a period, always the same number of ticks apart', () => {
    const clock = { tick: 0 }
    const schedule = new HeartbeatSchedule(60)
    const peers = Array.from({ length: 250 }, () => peer(clock))
    for (const p of peers) schedule.add(p)
    run(schedule, clock, 0, 60 * 5)
    for (const p of peers) {
      expect(p.pings).toHaveLength(5)
      for (let i = 1; i < p.pings.length; i++) expect(p.pings[i] - p.pings[i - 1]).toBe(60)
    }
  })

  it('spreads a burst of connections over the period: no tick pings more than its share', () => {
    const clock = { tick: 0 }
    const schedule = new HeartbeatSchedule(1800)
    const peers = Array.from({ length: 3000 }, () => peer(clock))
    for (const p of peers) schedule.add(p)
    const perTick = new Map()
    for (const p of peers) p.heartbeat = function () { perTick.set(clock.tick, (perTick.get(clock.tick) ?? 0) + 1) }
    run(schedule, clock, 0, 1800)
    expect([...perTick.values()].reduce((a, b) => a + b, 0)).toBe(3000)
    expect(Math.max(...perTick.values())).toBe(Math.ceil(3000 / 1800))
  })

  it('stops pinging a removed connection, also one removed while its slot is walked, and adds a connection once', () => {
    const clock = { tick: 0 }
    const schedule = new HeartbeatSchedule(1)
    const gone = peer(clock)
    const terminated = peer(clock)
    const stays = peer(clock)
    // A heartbeat that terminates its connection, which then leaves the schedule.
    terminated.heartbeat = function () { this.pings.push(clock.tick); schedule.remove(this) }
    for (const p of [gone, terminated, stays, stays]) schedule.add(p)
    schedule.remove(gone)
    run(schedule, clock, 0, 3)
    expect(gone.pings).toEqual([])
    expect(terminated.pings).toEqual([0])
    expect(stays.pings).toEqual([0, 1, 2])
  })

  it('keeps only the slots that have connections (an hour\'s period is 216,000 ticks)', () => {
    const clock = { tick: 0 }
    const schedule = new HeartbeatSchedule(216_000)
    const peers = Array.from({ length: 3 }, () => peer(clock))
    for (const p of peers) schedule.add(p)
    expect(schedule.slots.size).toBe(3)
    schedule.remove(peers[1])
    expect(schedule.slots.size).toBe(2)
    run(schedule, clock, 0, 3)
    expect(peers.map((p) => p.pings)).toEqual([[0], [], [2]])
  })
})
