/**
 * Sequences of a process in a cluster (../coordination/sequences.js): drop
 * ids and nonces come from the blocks the shared ledger reserved for this
 * process in PostgreSQL (shared-ledger.js: a seed's first block when its
 * account is loaded or its seed rotated, the next one ahead of need), so
 * two processes never hand out the same one.
 * @implements {import('../coordination/sequences.js').Sequences}
 */
export class ClusterSequences {
  /** @param {{ store: import('./shared-ledger.js').SharedLedgerStore }} options */
  constructor ({ store }) {
    this.store = store
  }

  /** The first block of drop ids (reserved once, unless openSharedLedger already did). */
  async start () {
    if (this.store.dropIds.end === 0) await this.store.startDropIds()
  }

  /** @param {{ id: string, nextNonce: number }} seed */
  takeNonce (seed) { return this.store.takeNonce(seed) }

  takeDropId () { return this.store.takeDropId() }
}
