/**
 * Where drop ids and nonces come from: the one place that hands them out,
 * in both modes (chosen once at start in modes.js). Both calls are
 * synchronous (a drop is accepted in the same call stack as its message)
 * and never give a number back.
 *
 * - LocalSequences (local-sequences.js): the process owns its ledger; drop
 *   ids continue from the ledger's highest, nonces are counted on the seed.
 * - ClusterSequences (../cluster/cluster-sequences.js): both come from
 *   blocks the shared PostgreSQL ledger reserved for this process, so two
 *   processes never hand out the same one.
 *
 * @typedef {object} Sequences
 * @property {() => Promise<void>} start before the first drop
 * @property {(seed: { id: string, nextNonce: number }) => number} takeNonce the seed's next nonce
 * @property {() => number} takeDropId the next drop id
 */
export {}
