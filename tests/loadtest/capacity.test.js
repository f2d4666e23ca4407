import { describe, it, expect } from 'vitest'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { stepFigures, stepTallies, capacityMarkdown, writeBetweenMarkers, parseCapacityArgs, capacitySection, BEGIN_MARKER, END_MARKER, CAPACITY_SECTION, CAPACITY_POSTGRES_SECTION, CAPACITY_STEERED_SECTION } from '../../loadtest/lean/capacity.js'
import { measureFloor } from '../../loadtest/lean/measure-server.js'
import { clusterStepFigures, clusterCapacityMarkdown, parseClusterCapacityArgs, CLUSTER_SECTION } from '../../loadtest/lean/cluster-capacity.js'

/** measureOurs()'s shape, with the figures that decide a step. */
function ours ({ tickP99 = 0.004, lagP99 = 0.006, ackP99 = 40, errors = 0, unsettled = 0, settled = 100, serverErrors = {}, delivery, sightingP99 = null, slowCommits = 0, generatorLateP99 = 12, writerWaitShare = 0.05 } = {}) {
  return {
    players: 2000,
    delivery,
    serverShare: 0.8,
    writerWaitShare,
    serverCpuS: 12,
    serverUsPerFrame: 19,
    othersShare: 0.05,
    analysis: { tick: { p99: tickP99 }, tickLag: { p99: lagP99 }, commit: { over50ms: slowCommits }, memory: { rssPerClient: 60_000 }, serverErrors },
    summary: {
      steady: { ackMs: { p50: 10, p99: ackP99, count: 15000 }, settledMs: { p50: 2500, p99: 4000 }, sightingMs: { p50: sightingP99 && sightingP99 / 2, p99: sightingP99 } },
      ackMs: { p99: ackP99 },
      dropsSent: 100,
      dropsSettled: settled,
      unsettled,
      errorCount: errors,
      window: { framesPerSecondPerPlayer: 21, bytesPerSecondPerPlayer: 3800 },
      cpu: { shareOfCore: 0.4, usPerFrame: 9.5, loopDelay: { p50Ms: 1, p99Ms: generatorLateP99, maxMs: 40 } }
    }
  }
}

describe('capacity steps', () => {
  it('holds only when every criterion does, and names the ones that fail', () => {
    const floor = { serverUsPerFrame: 10 }
    expect(stepFigures(ours(), floor)).toMatchObject({ holds: true, failed: [], ratio: 1.9 })
    expect(stepFigures(ours({ tickP99: 0.009 }), floor).failed).toEqual(['tick p99 < 8 ms'])
    expect(stepFigures(ours({ lagP99: 0.02 }), floor).failed).toEqual(['tick lag p99 < 16.7 ms'])
    expect(stepFigures(ours({ errors: 1 }), floor).failed).toEqual(['0 errors'])
    expect(stepFigures(ours({ serverErrors: { E_SLOW_CONSUMER: 2 } }), floor).failed).toEqual(['0 errors'])
    expect(stepFigures(ours({ settled: 99, unsettled: 1 }), floor).failed).toEqual(['every drop settled'])
    expect(stepFigures(ours({ ackP99: 250 }), null)).toMatchObject({ failed: ['drop → dropped p99 < 250 ms'], ratio: null })
    // Per player-second and per drop: 80% of a core over 2,000 players; 12 s of CPU over 15,000 drops.
    expect(stepFigures(ours(), null)).toMatchObject({ delivery: 'snapshots', serverUsPerPlayerSecond: 400, serverUsPerDrop: 800 })
    // Seeds mode has one criterion more: another player's drop seen by its room within 300 ms, p99.
    const seen = "another player's drop reaches its room p99 ≤ 300 ms (seeds)"
    expect(stepFigures(ours({ delivery: 'seeds', sightingP99: 280 }), null)).toMatchObject({ holds: true, sightingP99Ms: 280 })
    expect(stepFigures(ours({ delivery: 'seeds', sightingP99: 320 }), null).failed).toEqual([seen])
    expect(stepFigures(ours({ delivery: 'seeds' }), null).failed).toEqual([seen])
  })

  it('tables both delivery modes side by side, with the best of each', () => {
    const steps = [
      stepFigures(ours(), null),
      stepFigures(ours({ delivery: 'seeds', sightingP99: 260 }), null),
      stepFigures({ ...ours({ delivery: 'seeds', sightingP99: 400 }), players: 2500 }, null)
    ]
    const markdown = capacityMarkdown(steps, { rooms: 100, durationS: 20, pinned: false, date: new Date('2026-12-02T06:00:00Z') })
    expect(markdown).toContain('**Most players on one server process with every criterion met: snapshots 2,000, seeds 2,000**')
    expect(markdown).toMatch(/\| 2,000 \| seeds \| 80% \|.*\| 130 \/ 260 ms \|/)
    expect(markdown).toMatch(/\| 2,500 \| seeds \|.*fails: another player's drop/)
  })

  it('counts the commits over 50 ms beside how long the writer thread waited for the CPU, so a run says which held its commits', () => {
    const stalled = stepFigures(ours({ delivery: 'seeds', sightingP99: 420, ackP99: 330, slowCommits: 3, writerWaitShare: 0.564 }), null)
    expect(stalled).toMatchObject({ slowCommits: 3, writerWaitShare: 0.564, holds: false })
    const markdown = capacityMarkdown([stepFigures(ours(), null), stalled], { rooms: 100, durationS: 20, pinned: true })
    const header = markdown.split('\n').find((line) => line.startsWith('| players'))
    const column = header.split('|').map((cell) => cell.trim()).indexOf('commits > 50 ms, writer waiting for the CPU')
    expect(column).toBeGreaterThan(0)
    const cells = markdown.split('\n').filter((line) => /^\| 2,000 /.test(line)).map((line) => line.split('|').map((cell) => cell.trim())[column])
    expect(cells).toEqual(['0, 5%', '3, 56%'])
    // A run measured without the server's /metrics, or without /proc, has no figure, not a zero.
    expect(stepFigures({ ...ours(), analysis: null }, null).slowCommits).toBeNull()
    expect(stepFigures({ ...ours(), writerWaitShare: null }, null).writerWaitShare).toBeNull()
  })

  it("shows how late the generator's own event loop ran (p99), which every latency it measured includes", () => {
    const late = stepFigures(ours({ delivery: 'seeds', sightingP99: 290, generatorLateP99: 47 }), null)
    expect(late).toMatchObject({ generatorLateP99Ms: 47, holds: true })
    const markdown = capacityMarkdown([stepFigures(ours(), null), late], { rooms: 100, durationS: 20, pinned: true })
    const header = markdown.split('\n').find((line) => line.startsWith('| players')).split('|').map((cell) => cell.trim())
    const column = header.indexOf('generator CPU, µs/frame, loop late p99')
    expect(column).toBeGreaterThan(0)
    const cells = markdown.split('\n').filter((line) => /^\| 2,000 /.test(line)).map((line) => line.split('|').map((cell) => cell.trim())[column])
    expect(cells).toEqual(['40%, 9.50, 12 ms', '40%, 9.50, 47 ms'])
    // A generator that measured none (no steady window) shows none.
    expect(stepFigures({ ...ours(), summary: { ...ours().summary, cpu: { shareOfCore: 0.4, usPerFrame: 9.5, loopDelay: null } } }, null).generatorLateP99Ms).toBeNull()
  })

  it('with --repeat, holds a step only when every run of it did, and says how many did', () => {
    const seeds = (players, run, sightingP99) => ({ ...stepFigures({ ...ours({ delivery: 'seeds', sightingP99 }), players }, null), run })
    const steps = [
      { ...stepFigures(ours(), null), run: 1 }, seeds(2000, 1, 250),
      { ...stepFigures(ours({ tickP99: 0.009 }), null), run: 2 }, seeds(2000, 2, 260),
      seeds(3000, 1, 280), seeds(3000, 2, 320)
    ]
    expect(stepTallies(steps)).toEqual([
      { delivery: 'snapshots', players: 2000, runs: 2, held: 1 },
      { delivery: 'seeds', players: 2000, runs: 2, held: 2 },
      { delivery: 'seeds', players: 3000, runs: 2, held: 1 }
    ])
    const markdown = capacityMarkdown(steps, { rooms: 100, durationS: 20, pinned: true, date: new Date('2026-12-05T15:00:00Z') })
    expect(markdown).toContain('**Most players on one server process with every criterion met in every run of the step: snapshots none of the steps, seeds 2,000**')
    expect(markdown).toContain('Runs that held, per step: snapshots 2,000 1 of 2; seeds 2,000 2 of 2, 3,000 1 of 2.')
    expect(markdown).toMatch(/\| 3,000 \(run 2\) \| seeds \|.*fails: another player's drop/)
    // One run a step: the table as before, no run numbers.
    const single = capacityMarkdown([seeds(2000, 1, 250)], { rooms: 100, durationS: 20, pinned: true })
    expect(single).toContain('criterion met: seeds 2,000**')
    expect(single).not.toContain('(run 1)')
    expect(single).not.toContain('Runs that held')
  })

  it('writes the table between the markers, replacing the last one, or appends a section', () => {
    const file = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-capacity-')), 'RESULTS.md')
    fs.writeFileSync(file, `# Results\n\nbefore\n\n${BEGIN_MARKER}\nold table\n${END_MARKER}\n\nafter\n`)
    const steps = [stepFigures(ours(), { serverUsPerFrame: 10 }), stepFigures({ ...ours({ ackP99: 300 }), players: 2500 }, { serverUsPerFrame: 10 })]
    const markdown = capacityMarkdown(steps, { rooms: 100, durationS: 30, pinned: true, date: new Date('2026-12-01T20:00:00Z') })
    expect(markdown).toContain('**Most players on one server process with every criterion met: snapshots 2,000**')
    expect(markdown).toContain('| 2,500 |')
    expect(markdown).toContain('fails: drop → dropped p99 < 250 ms')
    writeBetweenMarkers(file, markdown)
    const text = fs.readFileSync(file, 'utf8')
    expect(text).not.toContain('old table')
    expect(text.startsWith('# Results\n\nbefore\n')).toBe(true)
    expect(text.endsWith('\n\nafter\n')).toBe(true)
    expect(text).toContain(markdown)
    fs.writeFileSync(file, '# Results\n')
    writeBetweenMarkers(file, 'table')
    expect(fs.readFileSync(file, 'utf8')).toBe(`# Results\n\n## Capacity (npm run loadtest:capacity)\n\n${BEGIN_MARKER}\ntable\n${END_MARKER}\n`)
  })

  it('reads its command line', () => {
    expect(parseCapacityArgs(['--steps', '1000, 2000', '--duration', '20s', '--all', '--no-results'])).toMatchObject({ steps: [1000, 2000], durationS: 20, all: true, writeResults: false, rooms: 100, deliveries: ['snapshots', 'seeds'] })
    expect(parseCapacityArgs(['--delivery', 'seeds'])).toMatchObject({ deliveries: ['seeds'] })
    expect(() => parseCapacityArgs(['--delivery', 'seeds,pixels'])).toThrow(/--delivery must be one of snapshots, seeds/)
    expect(() => parseCapacityArgs(['--steps', '1000,x'])).toThrow(/positive integer/)
    expect(parseCapacityArgs([]).ledger).toBe('sqlite')
    expect(parseCapacityArgs(['--ledger', 'postgres']).ledger).toBe('postgres')
    expect(() => parseCapacityArgs(['--ledger', 'redis'])).toThrow(/--ledger must be one of sqlite, postgres, got redis/)
    expect(parseCapacityArgs([]).repeat).toBe(1)
    expect(parseCapacityArgs(['--repeat', '3']).repeat).toBe(3)
    expect(() => parseCapacityArgs(['--repeat', '0'])).toThrow(/positive integer/)
    expect(parseCapacityArgs([]).steerLoopback).toBe(false)
    // Two generator threads unless told: one thread's lateness is in every latency it measures.
    expect(parseCapacityArgs([]).workers).toBe(2)
    expect(parseCapacityArgs(['--workers', '1']).workers).toBe(1)
    expect(capacityMarkdown([stepFigures(ours(), null)], { rooms: 100, durationS: 20, pinned: true, workers: 1 })).toContain('SQLite ledger, the generator in one worker thread.')
    expect(parseCapacityArgs(['--steer-loopback']).steerLoopback).toBe(true)
  })

  it('says when the loopback receive was steered off the server core, and keeps that table in a section of its own', () => {
    const steps = [stepFigures(ours(), null)]
    expect(capacityMarkdown(steps, { rooms: 100, durationS: 20, pinned: true })).not.toContain('steered')
    expect(capacityMarkdown(steps, { rooms: 100, durationS: 20, pinned: true, steered: true })).toContain("SQLite ledger, the generator in 2 worker threads, the loopback's receive processing steered to CPU 1 (--steer-loopback")
    expect(capacitySection({ ledger: 'sqlite' })).toBe(CAPACITY_SECTION)
    expect(capacitySection({ ledger: 'sqlite', steerLoopback: true })).toBe(CAPACITY_STEERED_SECTION)
    expect(capacitySection({ ledger: 'postgres', steerLoopback: true })).toBe(CAPACITY_POSTGRES_SECTION)
    expect(new Set([CAPACITY_SECTION.begin, CAPACITY_POSTGRES_SECTION.begin, CAPACITY_STEERED_SECTION.begin]).size).toBe(3)
  })

  it('says which ledger the table was measured with, and keeps a PostgreSQL table beside the SQLite one', () => {
    const steps = [stepFigures(ours(), null)]
    expect(capacityMarkdown(steps, { rooms: 100, durationS: 20, pinned: true })).toContain('generator to CPU 1, SQLite ledger, the generator in 2 worker threads.')
    const markdown = capacityMarkdown(steps, { rooms: 100, durationS: 20, pinned: true, ledger: 'postgres' })
    expect(markdown).toContain('generator and PostgreSQL to CPU 1, PostgreSQL ledger (flushed on every commit), the generator in 2 worker threads.')
    const file = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-capacity-')), 'RESULTS.md')
    fs.writeFileSync(file, `# Results\n\n${BEGIN_MARKER}\nsqlite table\n${END_MARKER}\n`)
    writeBetweenMarkers(file, markdown, CAPACITY_POSTGRES_SECTION)
    const text = fs.readFileSync(file, 'utf8')
    expect(text).toContain('sqlite table')
    expect(text).toContain(`${CAPACITY_POSTGRES_SECTION.begin}\n${markdown}\n${CAPACITY_POSTGRES_SECTION.end}`)
  })
})

describe('two-process capacity steps', () => {
  /** One process's analysis (run-analysis.js) with the figures that decide a step. */
  const analysis = ({ tickP99 = 0.004, lagP99 = 0.006, serverErrors = {} } = {}) => ({ tick: { p99: tickP99 }, tickLag: { p99: lagP99 }, serverErrors })
  const step = (players, analyses, over = {}) => clusterStepFigures({ players, analyses, summary: { ...ours().summary, redirects: 3, ...over }, serverShare: 1.2, generatorShare: 0.5 })

  it('holds only when every process does, and a followed E_WRONG_NODE is not an error', () => {
    expect(step(2000, [analysis(), analysis({ serverErrors: { E_WRONG_NODE: 40 } })])).toMatchObject({ holds: true, processes: 2, redirects: 3, tickP99Ms: 4, lagP99Ms: 6 })
    expect(step(2000, [analysis(), analysis({ lagP99: 0.03 })])).toMatchObject({ holds: false, failed: ['tick lag p99 < 16.7 ms'], lagP99Ms: 30 })
    expect(step(2000, [analysis({ tickP99: 0.01 }), analysis()]).failed).toEqual(['tick p99 < 8 ms'])
    expect(step(2000, [analysis(), analysis({ serverErrors: { E_WRONG_NODE: 1, E_SLOW_CONSUMER: 1 } })]).failed).toEqual(['0 errors'])
    expect(step(2000, [analysis(), {}]).failed).toEqual(['tick p99 < 8 ms', 'tick lag p99 < 16.7 ms'])
  })

  it('tables both modes with the ratio of players held, in its own section of RESULTS.md', () => {
    const modes = [
      { label: '1', steps: [step(1000, [analysis()]), step(1500, [analysis({ lagP99: 0.02 })])] },
      { label: '2', steps: [step(1000, [analysis(), analysis()]), step(1500, [analysis(), analysis()]), step(2000, [analysis(), analysis({ tickP99: 0.009 })])] }
    ]
    const markdown = clusterCapacityMarkdown(modes, { rooms: 100, durationS: 20, cpus: 2, date: new Date('2026-12-01T22:00:00Z') })
    expect(markdown).toContain('**Players held: one process 1,000, two processes (npm run cluster -- --workers 2) 1,500: 1.50×**')
    expect(markdown.split('\n').filter((line) => /^\| [12] \|/.test(line))).toHaveLength(5)
    const file = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-capacity-')), 'RESULTS.md')
    fs.writeFileSync(file, `# Results\n\n${BEGIN_MARKER}\none\n${END_MARKER}\n`)
    writeBetweenMarkers(file, markdown, CLUSTER_SECTION)
    writeBetweenMarkers(file, 'newer', CLUSTER_SECTION)
    expect(fs.readFileSync(file, 'utf8')).toBe(`# Results\n\n${BEGIN_MARKER}\none\n${END_MARKER}\n\n## ${CLUSTER_SECTION.heading}\n\n${CLUSTER_SECTION.begin}\nnewer\n${CLUSTER_SECTION.end}\n`)
  })

  it('reads its command line', () => {
    expect(parseClusterCapacityArgs(['--steps', '500,1000', '--ramp', '10s', '--no-results'])).toMatchObject({ steps: [500, 1000], rampS: 10, durationS: 20, rooms: 100, writeResults: false })
    expect(() => parseClusterCapacityArgs(['--steps', '0'])).toThrow(/positive integer/)
  })
})

describe('the WebSocket floor', () => {
  it('sends every client a frame every 50 ms and measures the bare server per frame', async () => {
    const floor = await measureFloor({ clients: 20, seconds: 1, pin: false })
    expect(floor.connected).toBe(20)
    // 20 clients × 20 frames/s over about a second (fewer when the machine is busy, never more).
    expect(floor.frames).toBeGreaterThanOrEqual(20)
    expect(floor.frames).toBeLessThanOrEqual(20 * 20 * floor.seconds * 1.5)
    expect(floor.serverCpuS).toBeGreaterThanOrEqual(0)
    expect(floor.serverUsPerFrame).toBeGreaterThanOrEqual(0)
    // The kernel's part is a part: never negative, never more than the whole.
    expect(floor.serverKernelUsPerFrame).toBeGreaterThanOrEqual(0)
    // Two quotients of /proc clock ticks: equal when all was kernel time, up to the last bit.
    expect(floor.serverKernelUsPerFrame).toBeLessThanOrEqual(floor.serverUsPerFrame * (1 + 1e-12))
    expect(floor.clientKernelUsPerFrame).toBeGreaterThanOrEqual(0)
    expect(floor.clientKernelUsPerFrame).toBeLessThanOrEqual(floor.clientUsPerFrame * (1 + 1e-12))
  })
})
