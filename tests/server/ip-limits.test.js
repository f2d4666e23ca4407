import { describe, it, expect } from 'vitest'
import { IpLimits, QUIET_SLACK } from '../../server/realtime/ip-limits.js'
import { TokenBucket } from '../../server/limits/token-bucket.js'

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

  it('enforces 1/N of every budget when N processes share them, and resizes the buckets of open addresses when N changes', () => {
    let now = 0
    const listeners = []
    const share = { workers: 2, onChange: (listener) => listeners.push(listener), close: async () => {} }
    const limits = new IpLimits({ dropRate: 4, joinRate: 2, maxSockets: 5, share, now: () => now })
    const entry = limits.acquire('10.0.0.1')
    const takes = (bucket, n) => Array.from({ length: n }, () => bucket.take()).filter(Boolean).length
    expect(takes(entry.drops, 10)).toBe(4) // 2 a second here, burst 4 (8 alone)
    expect(takes(entry.joins, 10)).toBe(2)
    limits.acquire('10.0.0.1')
    expect(limits.atSocketLimit('10.0.0.1')).toBe(true) // floor(5 / 2)
    share.workers = 1
    for (const listener of listeners) listener(1)
    expect(limits.atSocketLimit('10.0.0.1')).toBe(false)
    now += 1000
    expect(takes(entry.drops, 10)).toBe(4) // refilled at the whole rate now
    for (const listener of listeners) listener(4)
    expect(entry.drops.burst).toBe(2)
    expect(limits.maxSockets).toBe(1) // never below one socket
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

  it('budgets frames and bytes over all sockets of an address: past it only a quiet socket gets through', () => {
    let now = 0
    const limits = new IpLimits({ dropRate: 1, joinRate: 1, messageRate: 100, byteRate: 10_000, maxPayload: 4096, now: () => now })
    const entry = limits.acquire('10.0.0.4')
    const socket = () => new TokenBucket({ rate: 100, burst: 200, now: () => now })
    /** Frames one socket gets through before it is refused, sending `size`-byte frames as fast as it can. */
    const flood = (limiter, size, max = 1000) => {
      let admitted = 0
      while (admitted < max && limiter.take() && entry.admitFrame(size, limiter)) admitted++
      return admitted
    }
    // Eight sockets at full speed share the address's 200 frames (two seconds' worth), plus a few each.
    const admitted = Array.from({ length: 8 }, () => flood(socket(), 10))
    expect(admitted.reduce((a, b) => a + b, 0)).toBe(200 + 7 * (QUIET_SLACK + 1))
    // A quiet socket (never past its own rate) still gets its frames through.
    const quiet = socket()
    for (let i = 0; i < 50; i++) {
      now += 20
      expect(quiet.take() && entry.admitFrame(10, quiet)).toBe(true)
    }
    // Bytes: 20 KB (two seconds' worth) of 4 KB frames, then nothing more, quiet or not (a big frame never is).
    now += 10_000
    expect(flood(socket(), 4000)).toBe(5)
    expect(flood(socket(), 4000)).toBe(0)
    limits.release(entry)
    now += 10_000
    expect(limits.sweep()).toBe(1)
  })
})
