/**
 * The browser client's pure modules, run in Node: the playout clock of
 * SnapshotTimeline (out-of-order frames slotted in, stale ones dropped, the
 * render clock never going backwards), the socket URL the page connects to
 * before and after an E_WRONG_NODE redirect, the shorter forms of a bucket
 * label, and that the pages take the wire format from /protocol/ (the
 * server's own module), not a copy.
 */
import { describe, it, expect } from 'vitest'
import { readdirSync, readFileSync } from 'node:fs'
import { socketUrl } from '../../client/socket-url.js'
import { SnapshotTimeline } from '../../client/snapshot-timeline.js'
import { LABEL_FORMS, labelText } from '../../client/bucket-labels.js'

function lcg (seed) {
  let state = seed >>> 0
  return () => {
    state = (Math.imul(state, 1664525) + 1013904223) >>> 0
    return state / 2 ** 32
  }
}

describe('bucket label forms', () => {
  it('shortens a multiplier step by step: thousands in k, then no sign, then no leading zero', () => {
    const forms = (m) => LABEL_FORMS.map((form) => labelText(m, form))
    expect(forms(1000)).toEqual(['1000×', '1k×', '1k', '1k'])
    expect(forms(1500)).toEqual(['1500×', '1.5k×', '1.5k', '1.5k'])
    expect(forms(110)).toEqual(['110×', '110×', '110', '110'])
    expect(forms(0.52)).toEqual(['0.52×', '0.52×', '0.52', '.52'])
    expect(forms(0.201)).toEqual(['0.2×', '0.2×', '0.2', '.2'])
    expect(forms(16)).toEqual(['16×', '16×', '16', '16'])
  })
})

describe('SnapshotTimeline', () => {
  const snapshot = (tick) => ({ tick, slots: new Int32Array(0), xs: new Float32Array(0), ys: new Float32Array(0) })

  it('slots late frames in by tick, drops duplicates and frames older than the render point', () => {
    const timeline = new SnapshotTimeline({ tickRate: 60, snapshotEvery: 3 })
    expect(timeline.push(snapshot(3), 50)).toBe('accepted')
    expect(timeline.push(snapshot(9), 150)).toBe('accepted')
    expect(timeline.push(snapshot(6), 160)).toBe('accepted') // late, out of order
    expect(timeline.push(snapshot(6), 170)).toBe('duplicate')
    expect(timeline.buffer.map((s) => s.tick)).toEqual([3, 6, 9])
    expect(timeline.stats.outOfOrder).toBe(1)
    const { a, b } = timeline.bracket(7)
    expect([a.tick, b.tick]).toEqual([6, 9])
    expect(timeline.buffer.map((s) => s.tick)).toEqual([6, 9])
    expect(timeline.push(snapshot(4), 200)).toBe('stale')
    expect(timeline.stats.stale).toBe(1)
  })

  it('renders ~100 ms behind a steady server, further behind a jittery one, and never goes backwards', () => {
    for (const maxDelayMs of [0, 150]) {
      const random = lcg(42)
      const timeline = new SnapshotTimeline({ tickRate: 60, snapshotEvery: 3 })
      const arrivals = []
      for (let tick = 3; tick <= 1800; tick += 3) arrivals.push({ tick, at: tick * 1000 / 60 + 20 + random() * maxDelayMs })
      arrivals.sort((p, q) => p.at - q.at)
      let last = -Infinity
      let next = 0
      let lag = 0
      for (let now = 0; now < 30_500; now += 1000 / 60) {
        while (next < arrivals.length && arrivals[next].at <= now) timeline.push(snapshot(arrivals[next++].tick), arrivals[next - 1].at)
        const tick = timeline.advance(now)
        if (tick === null) continue
        expect(tick).toBeGreaterThanOrEqual(last)
        last = tick
        timeline.bracket(tick)
        lag = now * 60 / 1000 - tick
      }
      expect(timeline.stats.snaps).toBe(0)
      if (maxDelayMs === 0) {
        expect(timeline.delayMs).toBe(100)
        expect(lag * 1000 / 60).toBeGreaterThan(100)
        expect(lag * 1000 / 60).toBeLessThan(140)
      } else {
        expect(timeline.stats.outOfOrder).toBeGreaterThan(0)
        expect(timeline.delayMs).toBeGreaterThan(150)
      }
    }
  })

  it('learns the server\'s real tick rate', () => {
    const timeline = new SnapshotTimeline({ tickRate: 60, snapshotEvery: 3 })
    for (let tick = 3; tick <= 900; tick += 3) timeline.push(snapshot(tick), tick * 1000 / 180)
    expect(timeline.rate * 1000).toBeCloseTo(180, 3)
  })
})

describe('client socket URL', () => {
  it('connects beside the page, or to the process E_WRONG_NODE names, over ws or wss', () => {
    expect(socketUrl('http://localhost:8080/', 'abc')).toBe('ws://localhost:8080/ws?token=abc')
    expect(socketUrl('https://play.example/', 't')).toBe('wss://play.example/ws?token=t')
    // A page served under a process prefix, and an E_WRONG_NODE owner (no trailing slash).
    expect(socketUrl('http://lb:8080/n/server1/', 't')).toBe('ws://lb:8080/n/server1/ws?token=t')
    expect(socketUrl('http://lb:8080/n/server2', 't')).toBe('ws://lb:8080/n/server2/ws?token=t')
    expect(socketUrl('http://h/', 'a b&c')).toBe('ws://h/ws?token=a%20b%26c')
  })

  it('refuses anything but an absolute http(s) URL', () => {
    for (const bad of ['javascript:alert(1)', 'ftp://h/', '/n/1', '', 'not a url']) expect(socketUrl(bad, 't')).toBeNull()
  })
})

describe('client and protocol', () => {
  it('the pages import the wire format from /protocol/ and define none of it themselves', () => {
    const dir = new URL('../../client/', import.meta.url)
    const sources = readdirSync(dir).filter((name) => name.endsWith('.js')).map((name) => [name, readFileSync(new URL(name, dir), 'utf8')])
    for (const [name, source] of sources) {
      expect(source, name).not.toMatch(/function (decodeSnapshot|splitRoomFrame|parseRoomId|roomIdOf|encodeSnapshot)\b/)
      expect(source, name).not.toMatch(/SNAPSHOT_KIND\s*=|POSITION_BITS\s*=/)
    }
    // The player page's socket and room (room-connection.js) decode the frames and room ids with the server's modules.
    const connection = sources.find(([name]) => name === 'room-connection.js')[1]
    expect(connection).toMatch(/from '\/protocol\/snapshot-codec\.js'/)
    expect(connection).toMatch(/from '\/protocol\/room-id\.js'/)
  })
})
