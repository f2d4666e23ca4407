import { gameError } from '../errors.js'

/**
 * Sequences of a process in a cluster (../coordination/sequences.js): drop
 * ids and nonces are handed out here, synchronously, from the blocks the
 * shared ledger reserved for this process in PostgreSQL (shared-ledger.js):
 * a seed's block when its account is loaded or its seed rotated (the store
 * reports it, `watchNonceBlocks`), the next block ahead of need, so two
 * processes never hand out the same one. A reservation is never given back.
 * @implements {import('../coordination/sequences.js').Sequences}
 */
export class ClusterSequences {
  /** @param {{ store: import('./shared-ledger.js').SharedLedgerStore }} options */
  constructor ({ store }) {
    this.store = store
    /** @type {Map<string, { end: number, next: { start: number, end: number } | null, refilling: Promise<void> | null }>} by seed id */
    this.nonceBlocks = new Map()
    this.dropIds = { next: 0, end: 0, pending: null, nextBlock: null }
    store.watchNonceBlocks({
      reserved: (seedId, block) => { this.nonceBlocks.set(seedId, { end: block.end, next: null, refilling: null }) },
      retired: (seedId) => { this.nonceBlocks.delete(seedId) }
    })
  }

  /** Reserves the first block of drop ids. */
  async start () {
    const block = await this.store.reserveDropIds()
    this.dropIds.next = block.start
    this.dropIds.end = block.end
  }

  /** The next drop id (synchronous); a fresh block is fetched ahead of need. */
  takeDropId () {
    const ids = this.dropIds
    if (ids.next >= ids.end) {
      if (!ids.nextBlock) {
        this._refillDropIds()
        throw gameError('E_UNAVAILABLE', 'drop ids are being reserved; retry in a moment')
      }
      ids.next = ids.nextBlock.start
      ids.end = ids.nextBlock.end
      ids.nextBlock = null
    }
    const id = ids.next++
    if (ids.end - ids.next < this.store.dropIdBlock / 2) this._refillDropIds()
    return id
  }

  _refillDropIds () {
    const ids = this.dropIds
    if (ids.pending || ids.nextBlock) return
    ids.pending = this.store.reserveDropIds().then((block) => { ids.nextBlock = block }, () => {}).finally(() => { ids.pending = null })
  }

  /**
   * Takes the seed's next nonce from this process's reservation (synchronous).
   * @param {{ id: string, nextNonce: number }} seed
   */
  takeNonce (seed) {
    const block = this.nonceBlocks.get(seed.id)
    if (!block) throw gameError('E_UNAVAILABLE', 'no nonces reserved for this seed; reconnect')
    if (seed.nextNonce >= block.end) {
      if (!block.next) {
        this._refillNonces(seed.id, block)
        throw gameError('E_UNAVAILABLE', 'nonces are being reserved; retry in a moment')
      }
      seed.nextNonce = block.next.start
      block.end = block.next.end
      block.next = null
    }
    const nonce = seed.nextNonce++
    if (block.end - seed.nextNonce < this.store.nonceBlock / 2) this._refillNonces(seed.id, block)
    return nonce
  }

  _refillNonces (seedId, block) {
    if (block.refilling || block.next) return
    block.refilling = this.store.reserveNonces(seedId).then((next) => {
      if (next) block.next = next
    }, () => {}).finally(() => { block.refilling = null })
  }
}
