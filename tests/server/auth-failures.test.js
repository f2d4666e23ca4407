import { describe, it, expect, afterEach } from 'vitest'
import { LocalAuthFailures } from '../../server/limits/auth-failures.js'

/** The failed-authentication policy on a clock the test moves (limits/auth-failures.js). */
describe('LocalAuthFailures', () => {
  let limiter
  afterEach(() => limiter?.close())
  const policy = { limit: 3, windowMs: 60_000, blockMs: 10_000, maxBlockMs: 40_000 }

  function at (clock) {
    limiter = new LocalAuthFailures(policy, { now: () => clock.now })
    return limiter
  }

  it('blocks on the limit-th failure in a window, doubles each further block up to the longest, and starts over after a quiet spell', async () => {
    const clock = { now: 0 }
    const failures = at(clock)
    const blocks = []
    for (let round = 0; round < 5; round++) {
      expect(await failures.blockedFor('a')).toBe(0)
      expect(await failures.fail('a')).toBe(0)
      expect(await failures.fail('a')).toBe(0)
      const block = await failures.fail('a')
      blocks.push(block)
      expect(await failures.blockedFor('a')).toBe(block)
      // While blocked, failures are not counted (the guard refuses before any token is checked).
      expect(await failures.fail('a')).toBe(0)
      clock.now += block
    }
    expect(blocks).toEqual([10_000, 20_000, 40_000, 40_000, 40_000])
    // An address out of blocks for the longest block starts again from the first.
    clock.now += 40_000
    for (let i = 0; i < 2; i++) await failures.fail('a')
    expect(await failures.fail('a')).toBe(10_000)
  })

  it('forgets failures older than the window, and keeps keys apart', async () => {
    const clock = { now: 0 }
    const failures = at(clock)
    await failures.fail('a')
    await failures.fail('a')
    clock.now += 60_000
    expect(await failures.fail('a')).toBe(0)
    expect(await failures.fail('b')).toBe(0)
    expect(await failures.fail('a')).toBe(0)
    expect(await failures.fail('a')).toBe(10_000)
    expect(await failures.blockedFor('b')).toBe(0)
  })

  it('sweeps addresses past every window and block', async () => {
    const clock = { now: 0 }
    const failures = at(clock)
    for (let i = 0; i < 3; i++) await failures.fail('a')
    await failures.fail('b')
    clock.now += 60_000
    failures.sweep()
    expect([...failures.entries.keys()]).toEqual(['a'])
    clock.now += 10_000 + 40_000
    failures.sweep()
    expect(failures.entries.size).toBe(0)
  })
})
