import { describe, it, expect } from 'vitest'
import fs from 'node:fs'
import os from 'node:os'
import path from 'node:path'
import { steerLoopbackReceive, steerLoopbackReceiveUntilExit, cpuMask, LoopbackSteeringError } from '../../loadtest/driver/loopback-steering.js'

/**
 * --steer-loopback's setting (loadtest/driver/loopback-steering.js), on a
 * stand-in for /sys/class/net/lo/queues: the real one needs root, and a
 * test must not move the machine's network processing.
 */
function standInQueues (masks) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'plinko-lo-queues-'))
  masks.forEach((mask, i) => {
    fs.mkdirSync(path.join(dir, `rx-${i}`))
    fs.writeFileSync(path.join(dir, `rx-${i}`, 'rps_cpus'), `${mask}\n`)
  })
  fs.mkdirSync(path.join(dir, 'tx-0')) // transmit queues have no rps_cpus: left alone
  return dir
}

const maskOf = (dir, queue) => fs.readFileSync(path.join(dir, queue, 'rps_cpus'), 'utf8').trim()

describe('loopback receive steering', () => {
  it('writes the CPU mask to every receive queue and puts back what each had', () => {
    const queues = standInQueues(['0', '3'])
    const restore = steerLoopbackReceive(1, { queues })
    expect([maskOf(queues, 'rx-0'), maskOf(queues, 'rx-1')]).toEqual(['2', '2'])
    restore()
    expect([maskOf(queues, 'rx-0'), maskOf(queues, 'rx-1')]).toEqual(['0', '3'])
    restore() // twice (the run's end, then the process's exit): nothing more
    expect(maskOf(queues, 'rx-1')).toBe('3')
  })

  it('puts the steering back at the process\'s exit or a signal until told, then takes its listeners off', () => {
    const queues = standInQueues(['0'])
    const before = ['exit', 'SIGINT', 'SIGTERM'].map((event) => process.listenerCount(event))
    const restore = steerLoopbackReceiveUntilExit(1, { queues })
    expect(maskOf(queues, 'rx-0')).toBe('2')
    expect(['exit', 'SIGINT', 'SIGTERM'].map((event) => process.listenerCount(event))).toEqual(before.map((n) => n + 1))
    restore()
    expect(maskOf(queues, 'rx-0')).toBe('0')
    expect(['exit', 'SIGINT', 'SIGTERM'].map((event) => process.listenerCount(event))).toEqual(before)
    // Refused: nothing steered, no listener left behind.
    expect(() => steerLoopbackReceiveUntilExit(1, { queues: path.join(os.tmpdir(), 'plinko-no-such-queues') })).toThrow(LoopbackSteeringError)
    expect(['exit', 'SIGINT', 'SIGTERM'].map((event) => process.listenerCount(event))).toEqual(before)
  })

  it('refuses with E_LOOPBACK_STEERING, changing nothing, where it cannot write', () => {
    const missing = path.join(os.tmpdir(), 'plinko-no-such-queues')
    expect(() => steerLoopbackReceive(1, { queues: missing })).toThrow(LoopbackSteeringError)
    expect(() => steerLoopbackReceive(1, { queues: missing })).toThrow(/needs Linux and root/)
    const queues = standInQueues(['0', '0'])
    fs.rmSync(path.join(queues, 'rx-1', 'rps_cpus'))
    let error
    try { steerLoopbackReceive(1, { queues }) } catch (e) { error = e }
    expect(error.code).toBe('E_LOOPBACK_STEERING')
    expect(maskOf(queues, 'rx-0')).toBe('0') // the queue written before the failure is put back
  })

  it('writes masks as the kernel reads them: hexadecimal, eight digits a group', () => {
    expect(cpuMask(0)).toBe('1')
    expect(cpuMask(1)).toBe('2')
    expect(cpuMask(31)).toBe('80000000')
    expect(cpuMask(32)).toBe('1,00000000')
    expect(() => cpuMask(-1)).toThrow(RangeError)
  })
})
