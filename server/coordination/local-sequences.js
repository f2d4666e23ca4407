/**
 * Sequences of a server that runs alone (sequences.js): drop ids continue
 * from the ledger's highest, each seed's nonces are counted on the seed
 * (the ledger stores `nextNonce` with each batch).
 * @implements {import('./sequences.js').Sequences}
 */
export class LocalSequences {
  /** @param {{ store: { maxDropId: () => Promise<number> } }} options */
  constructor ({ store }) {
    this.store = store
    this.nextDropId = 1
  }

  async start () {
    this.nextDropId = (await this.store.maxDropId()) + 1
  }

  /** @param {{ nextNonce: number }} seed */
  takeNonce (seed) { return seed.nextNonce++ }

  takeDropId () { return this.nextDropId++ }
}
