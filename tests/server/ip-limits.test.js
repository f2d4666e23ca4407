import { describe, it, expect } from 'vitest'
import { IpLimits } from '../../server/realtime/ip-limits.js'

describe('IpLimits', () => {
  it('shares one drop and join budget between the sockets of an address, each address on its own', () => {
    let now = 0
    const limits = new IpLimits({ dropRate: 2, joinRate: 1, now: () => now })
    const a1 = limits.acquire('10.0.0.1')
    const a2 = limits.acquire('10.0.0.1')
    const b = limits.acquire('10.0.0.2')
    expect(a1).toBe(a2)
    expect(limits.openFrom('10.0.0.1')).toBe(2)
    const takes = (bucket, n) => Array.from({ length: n }, () => bucket.take()).filter(Boolean).length
    expect(takes(a1.drops, 3) + takes(a2.drops, 3)).toBe(4) // burst: 2 s worth
    expect(takes(b.drops, 6)).toBe(4)
    expect(takes(a1.joins, 5)).toBe(2)
    now += 1000
    expect(takes(a2.drops, 5)).toBe(2)
  })

  it('keeps an address with no socket open until its buckets have refilled, then forgets it', () => {
    let now = 0
    const limits = new IpLimits({ dropRate: 1, joinRate: 1, now: () => now })
    const entry = limits.acquire('10.0.0.3')
    entry.drops.take(); entry.drops.take()
    limits.release(entry)
    expect(limits.sweep()).toBe(0)
    const again = limits.acquire('10.0.0.3')
    expect(again).toBe(entry) // reconnecting does not refill the bucket
    expect(again.drops.take()).toBe(false)
    limits.release(again)
    now += 2000
    expect(limits.sweep()).toBe(1)
    expect(limits.openFrom('10.0.0.3')).toBe(0)
    expect(limits.acquire('10.0.0.3')).not.toBe(entry)
    expect(limits.sweep()).toBe(0) // open again: kept
  })
})
