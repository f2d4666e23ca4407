import path from 'node:path'
import { pathToFileURL } from 'node:url'
import { describe, it, expect } from 'vitest'
import { summarizeCpuProfile, areaOf, profileParts } from '../../loadtest/driver/cpu-profile-summary.js'
import { DROP_COST_PARTS } from '../../loadtest/lean/run.js'

const root = path.resolve(import.meta.dirname, '..', '..')
const url = (file) => pathToFileURL(path.join(root, file)).href

describe('CPU profile parts (the per-drop table)', () => {
  it('gives each busy sample to the deepest frame a part claims, idle left out', () => {
    const frame = (id, functionName, file, children = []) => ({ id, callFrame: { functionName, url: file ? url(file) : '', lineNumber: 0 }, children })
    const profile = {
      nodes: [
        frame(1, '(root)', null, [2, 6, 7, 9]),
        frame(2, 'tick', 'server/arena.js', [3, 4]),
        frame(3, 'step', 'server/rooms/room.js', [5]),
        frame(4, 'deliver', 'server/rooms/room.js'),
        frame(5, '_advanceBodies', 'engine/world.js'),
        frame(6, 'flushWrites', 'server/realtime/write-batcher.js', [8]),
        frame(7, '(idle)', null),
        frame(8, 'writev', null),
        frame(9, '_committed', 'server/game/drop-lifecycle.js', [10]),
        frame(10, '_sendToOwnerConnections', 'server/game/drop-lifecycle.js', [11]),
        frame(11, 'stringify', null)
      ],
      samples: [5, 3, 4, 8, 7, 11, 9, 2],
      timeDeltas: [100, 100, 100, 100, 100, 100, 100, 100]
    }
    const { busyMs, parts } = profileParts(profile, DROP_COST_PARTS)
    const ms = Object.fromEntries(parts.map((p) => [p.name, p.ms]))
    expect(busyMs).toBeCloseTo(0.7)
    expect(ms['physics (room steps)']).toBeCloseTo(0.2)
    expect(ms['room feeds (events and snapshots: encode, queue)']).toBeCloseTo(0.1)
    expect(ms['socket writes (every frame, at the end of the turn)']).toBeCloseTo(0.1)
    // A JSON.stringify under the owner's reply under the commit's apply is the owner's reply.
    expect(ms['owner replies (dropped, settled: JSON)']).toBeCloseTo(0.1)
    expect(ms['ledger commit (group commit, hand-over to the store, apply)']).toBeCloseTo(0.1)
    expect(ms.other).toBeCloseTo(0.1)
    expect(parts.reduce((sum, p) => sum + p.share, 0)).toBeCloseTo(1)
  })
})

describe('CPU profile summary', () => {
  it('attributes self time to functions and areas, and inclusive time to our functions', () => {
    const frame = (id, functionName, file, children = []) => ({ id, callFrame: { functionName, url: file ? url(file) : '', lineNumber: 9 }, children })
    const profile = {
      nodes: [
        frame(1, '(root)', null, [2, 5]),
        frame(2, 'tick', 'server/arena.js', [3, 4]),
        frame(3, 'step', 'engine/world.js'),
        frame(4, 'send', 'node_modules/ws/lib/sender.js'),
        frame(5, '(idle)', null)
      ],
      samples: [3, 3, 4, 5, 2],
      timeDeltas: [100, 100, 100, 100, 100],
      startTime: 0,
      endTime: 500
    }
    const summary = summarizeCpuProfile(profile)
    expect(summary.totalMs).toBeCloseTo(0.5)
    expect(summary.areas.find((a) => a.area === 'engine').share).toBeCloseTo(0.4)
    expect(summary.areas.find((a) => a.area === 'npm:ws').share).toBeCloseTo(0.2)
    expect(summary.selfTop[0].name).toBe('step engine/world.js:10')
    expect(summary.inclusiveTop[0]).toMatchObject({ name: 'tick server/arena.js:10', share: 0.8 })
    // A time range keeps only the samples inside it.
    expect(summarizeCpuProfile(profile, { from: 250, to: 500 }).totalMs).toBeCloseTo(0.3)
  })

  it('names areas', () => {
    expect(areaOf({ functionName: '(garbage collector)', url: '' })).toBe('(garbage collector)')
    expect(areaOf({ functionName: 'writev', url: '' })).toBe('native')
    expect(areaOf({ functionName: 'x', url: 'node:net' })).toBe('node')
    expect(areaOf({ functionName: 'x', url: url('node_modules/@fastify/websocket/index.js') })).toBe('npm:@fastify/websocket')
    expect(areaOf({ functionName: 'x', url: url('server/arena.js') })).toBe('server')
  })
})
