import { describe, it, expect } from 'vitest'
import { LeanPlayer, PlayerStats, DropSightings, MAX_REDIRECTS, frameTick, milli } from '../../loadtest/lean/lean-player.js'
import { encodeSnapshot, encodeRoomFrame } from '../../protocol/snapshot-codec.js'
import { encodeDropEvents } from '../../protocol/drop-events-codec.js'
import { ENGINE_VERSION } from '../../engine/index.js'

function player ({ balance = 100 } = {}) {
  const stats = new PlayerStats()
  const sent = []
  let clock = 0
  const p = new LeanPlayer({ room: '16-medium.2', bet: 10, stats, send: (text) => sent.push(JSON.parse(text)), now: () => clock })
  p.receiveText(JSON.stringify({ type: 'welcome', playerId: 'p1', balance }), 0)
  p.receiveText(JSON.stringify({ type: 'joined', room: '16-medium.2', snapshotEvery: 3 }), 0)
  return { p, stats, sent, at: (t) => { clock = t } }
}

const snapshot = (tick) => encodeSnapshot(tick, new Uint8Array([1, 0, 1]), 3, new Float64Array([10, 0, 20]), new Float64Array([30, 0, 40]))

describe('LeanPlayer', () => {
  it('joins its room on welcome and sends drops with increasing refs once joined', () => {
    const { p, sent, stats } = player()
    expect(sent[0]).toEqual({ type: 'join', room: '16-medium.2' })
    expect(p.drop()).toBe(true)
    expect(p.drop()).toBe(true)
    expect(sent.slice(1)).toEqual([{ type: 'drop', bet: 10, ref: 1 }, { type: 'drop', bet: 10, ref: 2 }])
    p.leave()
    expect(p.drop()).toBe(false)
    expect(stats.dropsSent).toBe(2)
  })

  it('follows the balance through dropped and settled and times both', () => {
    const { p, stats, at } = player({ balance: 100 })
    at(1000)
    p.drop()
    p.receiveText(JSON.stringify({ type: 'dropped', player: 'p1', ref: 1, dropId: 'd1', bet: 10, balance: 90 }), 1020)
    expect(p.drained).toBe(false)
    p.receiveText(JSON.stringify({ type: 'settled', player: 'p1', dropId: 'd1', bet: 10, multiplier: 1.234, payout: 12.34, ticks: 121, balance: 102.34 }), 3100)
    expect(stats.errorCount).toBe(0)
    expect(p.drained).toBe(true)
    expect(p.balance).toBe(milli(102.34))
    expect(stats.ackMs.toArray()).toEqual(new Float64Array([20]))
    expect(stats.settledMs.toArray()).toEqual(new Float64Array([2100]))
    expect(stats.settleOverheadMs.toArray()[0]).toBeCloseTo(100, 6)
    expect([stats.dropsAcked, stats.dropsSettled]).toEqual([1, 1])
  })

  it('counts a balance that does not follow, a wrong payout, unknown drops and settles', () => {
    const { p, stats } = player({ balance: 100 })
    p.drop()
    p.receiveText(JSON.stringify({ type: 'dropped', player: 'p1', ref: 1, dropId: 'd1', bet: 10, balance: 91 }), 1)
    p.receiveText(JSON.stringify({ type: 'settled', player: 'p1', dropId: 'd1', bet: 10, multiplier: 2, payout: 19.999, ticks: 60, balance: 110.999 }), 2)
    p.receiveText(JSON.stringify({ type: 'dropped', player: 'p1', ref: 77, dropId: 'd9', bet: 10, balance: 100.999 }), 3)
    p.receiveText(JSON.stringify({ type: 'settled', player: 'p1', dropId: 'd8', bet: 10, multiplier: 0, payout: 0, ticks: 60, balance: 100.999 }), 4)
    expect(Object.fromEntries(stats.errors)).toEqual({ X_BALANCE_MISMATCH: 1, X_BAD_PAYOUT: 1, X_UNKNOWN_DROP: 1, X_UNKNOWN_SETTLE: 1 })
    expect(stats.balanceMismatches).toBe(1)
  })

  it('ignores the other players\' events and counts error frames, freeing a refused drop', () => {
    const { p, stats } = player()
    p.receiveText(JSON.stringify({ type: 'dropped', player: 'p2', ref: 1, dropId: 'x', bet: 10, balance: 5 }), 1)
    p.drop()
    p.receiveText(JSON.stringify({ type: 'error', code: 'E_RATE_LIMITED', message: 'slow down', ref: 1 }), 2)
    expect(Object.fromEntries(stats.errors)).toEqual({ E_RATE_LIMITED: 1 })
    expect(stats.dropsRefused).toBe(1)
    expect(p.drained).toBe(true)
  })

  it('counts drops still pending or in flight when the socket closes, and a close it did not ask for', () => {
    const { p, stats } = player()
    p.drop()
    p.drop()
    p.receiveText(JSON.stringify({ type: 'dropped', player: 'p1', ref: 1, dropId: 'd1', bet: 10, balance: 90 }), 1)
    p.closed(1013, false)
    expect(stats.unsettled).toBe(2)
    expect(Object.fromEntries(stats.errors)).toEqual({ WS_CLOSE_1013: 1 })
    p.closed(1013, false)
    expect(stats.finished).toBe(1)
  })

  it('counts a player that leaves before it joined its room', () => {
    const stats = new PlayerStats()
    const p = new LeanPlayer({ room: 'r', bet: 10, stats, send: () => {} })
    p.receiveText(JSON.stringify({ type: 'welcome', playerId: 'p1', balance: 100 }), 0)
    p.closed(1000, true)
    expect(Object.fromEntries(stats.errors)).toEqual({ X_NOT_JOINED: 1 })
    const { p: joined, stats: joinedStats } = player()
    joined.closed(1000, true)
    expect(joinedStats.errorCount).toBe(0)
  })

  it('reads snapshot ticks from room frames and bare snapshots, and counts ticks out of order', () => {
    const { p, stats } = player()
    const room = encodeRoomFrame('[{"type":"dropped","player":"p2"}]', snapshot(300))
    expect(frameTick(room, 0, room.length)).toBe(300)
    expect(frameTick(snapshot(2 ** 32 - 1), 0, 12)).toBe(2 ** 32 - 1)
    const padded = new Uint8Array(room.length + 4)
    padded.set(room, 4)
    expect(frameTick(padded, 4, padded.length)).toBe(300)
    expect(frameTick(new Uint8Array([3, 0, 0]), 0, 3)).toBe(-1)
    expect(frameTick(room, 0, 8)).toBe(-1)
    const textBytes = stats.bytes
    p.receiveBinary(room, 0, room.length)
    const next = encodeRoomFrame('[]', snapshot(303))
    p.receiveBinary(next, 0, next.length)
    p.receiveBinary(room, 0, room.length)
    p.receiveBinary(new Uint8Array([9]), 0, 1)
    expect(stats.frames).toBe(4)
    expect(stats.bytes - textBytes).toBe(room.length * 2 + next.length + 1)
    expect(Object.fromEntries(stats.errors)).toEqual({ X_TICK_ORDER: 1, X_BAD_FRAME: 1 })
  })

  it('follows E_WRONG_NODE to a loopback owner before joining, at most MAX_REDIRECTS times, and counts anything else as an error', () => {
    const stats = new PlayerStats()
    const sent = []
    const moves = []
    const p = new LeanPlayer({ room: '16-low', bet: 10, stats, send: (text) => sent.push(JSON.parse(text)), redirect: (url) => moves.push(url) })
    const wrongNode = (owner) => JSON.stringify({ type: 'error', code: 'E_WRONG_NODE', message: 'elsewhere', room: '16-low', owner })
    p.receiveText(JSON.stringify({ type: 'welcome', playerId: 'p1', balance: 100 }), 0)
    p.receiveText(wrongNode('http://127.0.0.1:8080/n/1'), 1)
    expect(moves).toEqual(['ws://127.0.0.1:8080/n/1/ws'])
    expect(stats.errorCount).toBe(0)
    // The new connection's welcome joins again; a second and third redirect are followed, a fourth is an error.
    for (let i = 0; i < MAX_REDIRECTS; i++) {
      p.receiveText(JSON.stringify({ type: 'welcome', playerId: 'p1', balance: 100 }), 2)
      p.receiveText(wrongNode(`http://localhost:${9000 + i}`), 3)
    }
    expect(moves).toHaveLength(MAX_REDIRECTS)
    expect(stats.redirects).toBe(MAX_REDIRECTS)
    expect(Object.fromEntries(stats.errors)).toEqual({ E_WRONG_NODE: 1 })
    expect(sent.filter((m) => m.type === 'join')).toHaveLength(MAX_REDIRECTS + 1)

    // Never off this machine, and never once joined.
    const far = new LeanPlayer({ room: 'r', bet: 10, stats: new PlayerStats(), send: () => {}, redirect: (url) => moves.push(url) })
    far.receiveText(wrongNode('http://203.0.113.9:8080'), 0)
    expect(Object.fromEntries(far.stats.errors)).toEqual({ E_WRONG_NODE: 1 })
    const { p: joined, stats: joinedStats } = player()
    joined.redirect = (url) => moves.push(url)
    joined.receiveText(wrongNode('http://127.0.0.1:8080'), 0)
    expect(Object.fromEntries(joinedStats.errors)).toEqual({ E_WRONG_NODE: 1 })
    expect(moves).toHaveLength(MAX_REDIRECTS)
  })

  it('in seeds mode asks for it, decodes drop-events frames and times another player\'s drop from its owner\'s send on the same clock', () => {
    const stats = new PlayerStats()
    stats.steadyFrom = 0
    stats.steadyTo = 1e9
    const sightings = new DropSightings(stats)
    let clock = 0
    const make = (playerId) => {
      const sent = []
      const p = new LeanPlayer({ room: '9-low', bet: 10, stats, delivery: 'seeds', sightings, send: (text) => sent.push(JSON.parse(text)), now: () => clock })
      p.receiveText(JSON.stringify({ type: 'welcome', playerId, balance: 100 }), 0)
      p.receiveText(JSON.stringify({ type: 'joined', room: '9-low', delivery: 'seeds' }), 0)
      return { p, sent }
    }
    const owner = make('aaaaaaaaaaaaaaaa')
    const watcher = make('bbbbbbbbbbbbbbbb')
    expect(watcher.sent[0]).toEqual({ type: 'join', room: '9-low', delivery: 'seeds' })
    const event = (id, playerId) => ({ id, bet: 10, startTick: 5, slot: 0, engineVersion: ENGINE_VERSION, playerId, dropSeed: 'c'.repeat(64) })
    const frame = (tick, events) => encodeDropEvents(tick, '0'.repeat(16), events)

    clock = 1000
    owner.p.drop()
    owner.p.receiveText(JSON.stringify({ type: 'dropped', player: 'aaaaaaaaaaaaaaaa', ref: 1, dropId: 7, bet: 10, balance: 90 }), 1010)
    // Seen by the watcher 180 ms after its owner sent it; by the owner itself, skipped.
    watcher.p.receiveBinary(frame(30, [event(7, 'aaaaaaaaaaaaaaaa')]), 0, 79, 1180)
    owner.p.receiveBinary(frame(30, [event(7, 'aaaaaaaaaaaaaaaa')]), 0, 79, 1181)
    // An event that beats its owner's `dropped` is timed once that comes.
    clock = 2000
    owner.p.drop()
    watcher.p.receiveBinary(frame(45, [event(8, 'aaaaaaaaaaaaaaaa'), event(9, 'cccccccccccccccc')]), 0, 143, 2100)
    owner.p.receiveText(JSON.stringify({ type: 'dropped', player: 'aaaaaaaaaaaaaaaa', ref: 2, dropId: 8, bet: 10, balance: 80 }), 2150)
    expect(stats.errorCount).toBe(0)
    expect(stats.eventFrames).toBe(3)
    // The watcher saw 7, 8 and 9; 9's owner is no player of this worker: counted, not timed.
    expect(stats.eventsSeen).toBe(3)
    expect([...stats.steadySightingMs.toArray()]).toEqual([180, 100])
    // Each carried by a frame some room ticks after the ball's release (start tick 5): at ticks 30 and 45.
    expect([...stats.steadySightingTicks.toArray()]).toEqual([25, 40])

    // A snapshot on a seeds socket, a truncated frame and a tick going back are errors.
    watcher.p.receiveBinary(snapshot(50), 0, snapshot(50).length, 2200)
    const truncated = frame(60, [event(10, 'aaaaaaaaaaaaaaaa')])
    watcher.p.receiveBinary(truncated, 0, 40, 2300)
    watcher.p.receiveBinary(frame(40, []), 0, 15, 2400)
    expect(Object.fromEntries(stats.errors)).toEqual({ X_UNEXPECTED_SNAPSHOT: 1, X_BAD_FRAME: 1, X_TICK_ORDER: 1 })
  })
})
