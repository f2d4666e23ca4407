import path from 'node:path'
import { pathToFileURL } from 'node:url'
import { describe, it, expect } from 'vitest'
import { summarizeCpuProfile, areaOf } from '../../loadtest/driver/cpu-profile-summary.js'

const root = path.resolve(import.meta.dirname, '..', '..')
const url = (file) => pathToFileURL(path.join(root, file)).href

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
