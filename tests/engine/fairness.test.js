import { describe, it, expect } from 'vitest'
import { createHash, createHmac } from 'node:crypto'
import { sha256Hex, hmacSha256Hex, deriveDropSeed, dropSeedMessage } from '../../engine/fairness.js'
import { verifyDrop } from '../../engine/verify-drop.js'
import { createBoard } from '../../engine/board.js'
import { simulateDrop } from '../../engine/drop-simulator.js'
import { ENGINE_VERSION } from '../../engine/version.js'
import { dropSeedSync } from '../../cli/drop-seeds.js'

// Published vectors: FIPS 180-2 (SHA-256) and RFC 4231 test case 2 (HMAC-SHA256).
const SHA256_ABC = 'ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad'
const RFC4231_CASE2 = '5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843'

describe('fairness hashing (WebCrypto)', () => {
  it('matches the published SHA-256 and HMAC-SHA256 vectors', async () => {
    expect(await sha256Hex('abc')).toBe(SHA256_ABC)
    expect(await hmacSha256Hex('Jefe', 'what do ya want for nothing?')).toBe(RFC4231_CASE2)
  })

  it('matches an independent implementation (node:crypto) on UTF-8 seeds', async () => {
    const cases = [
      ['server-seed', 'client-seed', 0],
      ['3f1c0ffee', 'lucky', 42],
      ['ünïcødé 🎲 seed', 'клиент', 9007199254740991],
      ['s', '', 1]
    ]
    for (const [serverSeed, clientSeed, nonce] of cases) {
      const message = `${clientSeed}:${nonce}`
      expect(dropSeedMessage(clientSeed, nonce)).toBe(message)
      const expected = createHmac('sha256', Buffer.from(serverSeed, 'utf8')).update(Buffer.from(message, 'utf8')).digest('hex')
      expect(await deriveDropSeed(serverSeed, clientSeed, nonce)).toBe(expected)
      expect(dropSeedSync(serverSeed, clientSeed, nonce)).toBe(expected)
      expect(await sha256Hex(serverSeed)).toBe(createHash('sha256').update(serverSeed, 'utf8').digest('hex'))
    }
  })

  it('rejects malformed inputs instead of deriving a seed', async () => {
    await expect(deriveDropSeed('', 'c', 0)).rejects.toThrow(TypeError)
    await expect(deriveDropSeed('s', 'c', -1)).rejects.toThrow(RangeError)
    await expect(deriveDropSeed('s', 'c', 1.5)).rejects.toThrow(RangeError)
    await expect(deriveDropSeed('s', 42, 0)).rejects.toThrow(TypeError)
  })

  it('verifyDrop recomputes the whole chain: commitment, drop seed and outcome', async () => {
    const result = await verifyDrop({ serverSeed: 'revealed-seed', clientSeed: 'player', nonce: 7, rows: 12, risk: 'high' })
    expect(result.serverSeedHash).toBe(createHash('sha256').update('revealed-seed').digest('hex'))
    expect(result.dropSeed).toBe(createHmac('sha256', 'revealed-seed').update('player:7').digest('hex'))
    const board = createBoard({ rows: 12, risk: 'high' })
    const outcome = simulateDrop(board, result.dropSeed)
    expect(result).toEqual({ ...outcome, serverSeedHash: result.serverSeedHash, dropSeed: result.dropSeed, engineVersion: ENGINE_VERSION })
    expect(result.multiplier).toBe(board.multipliers[result.bucket])
  })
})
